"""Estimate the household language model and write what the recogniser loads: the model
(pocketsphinx's binary format), the dictionary cut down to its words, and a model card."""

from __future__ import annotations

import json
import re
import tempfile
from pathlib import Path

import yaml

from core.checkpoint import atomic_write_bytes
from core.paths import WORLDS_DIR
from dialogue.speech.config import SpeechConfig
from dialogue.speech.engines import wheel_model_dir
from dialogue.speech.training.corpus import (
    DEV_FILE,
    HELD_OUT_FILES,
    build_corpus,
    knowledge_questions,
    tsv_lines,
)
from dialogue.speech.training.language_model import NGramModel, ngram_counts
from dialogue.speech.words import spoken_words

ALTERNATE = re.compile(r"\(\d+\)$")   # "read(2)": a second pronunciation of "read"


def full_dictionary() -> dict[str, list[str]]:
    """pocketsphinx's en-US pronunciation dictionary: each word's lines, alternates kept."""
    entries: dict[str, list[str]] = {}
    path = wheel_model_dir() / "cmudict-en-us.dict"
    for line in path.read_text(encoding="utf-8").splitlines():
        if line.strip():
            head = line.split(maxsplit=1)[0]
            entries.setdefault(ALTERNATE.sub("", head), []).append(line)
    return entries


def evaluation_lines() -> list[str]:
    """Lines the robot is evaluated on, which the model must not learn: the recogniser's
    held-out lines, the requests settings are chosen on (``speech_dev.tsv``), the held-out
    knowledge questions (bench/bench_asr_threshold.py says them) and every line people say
    in the shipped household scenarios."""
    lines = [text for name in (*HELD_OUT_FILES, DEV_FILE) for _, text in tsv_lines(name)]
    lines += knowledge_questions()
    for world in sorted(WORLDS_DIR.glob("*.yaml")):
        scenario = yaml.safe_load(world.read_text(encoding="utf-8")) or {}
        for person in scenario.get("people", []):
            for event in person.get("events", []):
                say = event.get("say")
                lines += [say["text"] if isinstance(say, dict) else say] if say else []
                lines += [event["encourage"]] if event.get("encourage") else []
    return lines


def evaluation_words() -> set[tuple[str, ...]]:
    """The spoken words of every :func:`evaluation_lines` line, which no model may learn."""
    return {tuple(spoken_words(t)) for t in evaluation_lines()}


def train_language_model(cfg: SpeechConfig, out_dir: Path) -> dict[str, object]:
    """Build the corpus, estimate the model and write ``out_dir/household.lm.bin``,
    ``household.dict`` and ``household.json`` (the training figures for the model card)."""
    from pocketsphinx import Config, LogMath
    from pocketsphinx import NGramModel as SphinxModel

    entries = full_dictionary()
    corpus = build_corpus(cfg.train, set(entries))
    held_out = evaluation_words()
    left_out = 0
    for name, sentences in corpus.sources.items():
        corpus.sources[name] = [s for s in sentences if tuple(s) not in held_out]
        left_out += len(sentences) - len(corpus.sources[name])
    weights = cfg.train.weights.model_dump()
    counts = ngram_counts([(weights[name], sentences)
                           for name, sentences in corpus.sources.items()],
                          cfg.train.order, cfg.train.min_count)
    model = NGramModel.estimate(counts, cfg.train.discount)
    out_dir.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        arpa = Path(tmp) / "household.arpa"
        model.save(arpa)
        binary = Path(tmp) / "household.lm.bin"
        SphinxModel(Config(loglevel="FATAL"), LogMath(), str(arpa)).write(
            str(binary), SphinxModel.str_to_type("bin"))
        atomic_write_bytes(out_dir / "household.lm.bin", binary.read_bytes())
    vocabulary = sorted(w for (w,) in counts[0] if w in entries)
    lines = [line for w in vocabulary for line in entries[w]]
    atomic_write_bytes(out_dir / "household.dict", ("\n".join(lines) + "\n").encode())
    figures = {**corpus.counts, "evaluation_lines_left_out": left_out,
               "vocabulary": len(vocabulary),
               "ngrams": [len(p) for p in model.probs], "order": cfg.train.order,
               "discount": cfg.train.discount}
    atomic_write_bytes(out_dir / "household.json", (json.dumps(figures, indent=2) + "\n").encode())
    return figures
