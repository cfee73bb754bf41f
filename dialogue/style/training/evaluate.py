"""``companion eval style``: the field's measures on the held-out split, and example tables.

The test split is re-derived from the data settings stored in ``style.pt``, so it is the
one the model never saw. Every test sentence is transferred to the opposite style (raw model
outputs: the confidence check of :mod:`dialogue.style.transfer` is not applied) and scored with
:mod:`dialogue.style.training.metrics`. The result holds ``accuracy``, ``self_bleu``, ``perplexity``
and ``classifier_accuracy`` (the judge's own accuracy on the untouched test sentences),
per-direction figures, the latency of translating one sentence, and examples like the
thesis's Tables 4.5-4.6 and the chit-chat table of §4.2.
"""

from __future__ import annotations

import statistics
import time
from pathlib import Path
from typing import Any

from dialogue.style.config import CLASSIFIER_FILE, LM_FILE, STYLE_FILE, DataConfig
from dialogue.style.decode import transfer_ids
from dialogue.style.files import load_classifier, load_lm
from dialogue.style.training.data import load_splits
from dialogue.style.training.metrics import accuracy, perplexity, self_bleu
from dialogue.style.training.train import balanced_subset
from dialogue.style.transfer import StyleTransfer, replace_unknown

# Chit-chat replies of thesis §4.2 ("Chit-Chat bot + Text Style Translation").
CHITCHAT = ["pretty good , how about you ?", "no , i feel very sad today .",
            "it is very delicious !", "it is gross ."]
DIRECTIONS = ("negative_to_positive", "positive_to_negative")


def evaluate(model_dir: Path, split: str = "test", limit: int | None = None,
             beam_size: int | None = None, data_dir: Path | None = None,
             n_examples: int = 8) -> dict[str, Any]:
    """Score the model folder's ``style.pt`` with its ``classifier.pt`` and ``lm.pt``."""
    transfer = StyleTransfer.load(model_dir / STYLE_FILE, beam_size=beam_size)
    judge, judge_vocab, _ = load_classifier(model_dir / CLASSIFIER_FILE)
    lm, lm_vocab, _ = load_lm(model_dir / LM_FILE)
    data_cfg = DataConfig(**transfer.meta["data"])
    if data_dir is not None:
        data_cfg = data_cfg.model_copy(update={"dir": data_dir})
    sp = load_splits(data_cfg)[split]
    if limit is not None:
        sources, labels = balanced_subset(sp, limit)
    else:
        sources, labels = sp.sentences, sp.labels
    vocab = transfer.vocab
    start = time.perf_counter()
    raw = transfer_ids(transfer.model, [vocab.encode(s) for s in sources], labels,
                       transfer.beam_size, transfer.max_extra_words, transfer.disc_weight)
    seconds = time.perf_counter() - start
    outputs = [replace_unknown(vocab.decode(o), s, vocab) for o, s in zip(raw, sources,
                                                                          strict=True)]
    flipped = [1 - y for y in labels]
    result: dict[str, Any] = {
        "accuracy": accuracy(judge, judge_vocab, outputs, flipped),
        "self_bleu": self_bleu(outputs, sources),
        "perplexity": perplexity(lm, lm_vocab, outputs),
        "classifier_accuracy": accuracy(judge, judge_vocab, sources, labels),
        "source_perplexity": perplexity(lm, lm_vocab, sources),
        "split": split, "sentences": len(sources), "beam_size": transfer.beam_size,
        "batch_seconds": round(seconds, 2),
        "ms_per_sentence": _latency(transfer, sources[:20]),
    }
    examples: dict[str, list[list[str]]] = {}
    for source_label, name in enumerate(DIRECTIONS):
        idx = [i for i, y in enumerate(labels) if y == source_label]
        src = [sources[i] for i in idx]
        out = [outputs[i] for i in idx]
        result[name] = {"accuracy": accuracy(judge, judge_vocab, out, [1 - source_label] * len(
            out)), "self_bleu": self_bleu(out, src), "sentences": len(src)}
        examples[name] = [[" ".join(s), " ".join(o)] for s, o in
                          zip(src[:n_examples], out[:n_examples], strict=True)]
    examples["chitchat"] = [[s, *(transfer.translate_detailed([s], to)[0].transferred
                                  for to in ("negative", "positive"))] for s in CHITCHAT]
    result["examples"] = examples
    return result


def _latency(transfer: StyleTransfer, sentences: list[list[str]]) -> float:
    """Median milliseconds of ``translate`` on one sentence at a time."""
    times = []
    for s in sentences:
        start = time.perf_counter()
        transfer.translate([" ".join(s)], "positive")
        times.append((time.perf_counter() - start) * 1000)
    return round(statistics.median(times), 2) if times else float("nan")


def examples_markdown(result: dict[str, Any]) -> str:
    """Tables like the thesis's 4.5 (positive -> negative), 4.6 and the §4.2 chit-chat one."""
    ex = {k: [[c.replace("|", "\\|") for c in row] for row in rows]
          for k, rows in result["examples"].items()}
    parts = []
    for title, key, head in (
            ("Positive sentences transferred to negative (cf. Table 4.5)",
             "positive_to_negative", ("Positive (original)", "Negative (transferred)")),
            ("Negative sentences transferred to positive (cf. Table 4.6)",
             "negative_to_positive", ("Negative (original)", "Positive (transferred)"))):
        rows = [f"| {a} | {b} |" for a, b in ex[key]]
        parts.append("\n".join([f"### {title}", "", f"| {head[0]} | {head[1]} |",
                                "| --- | --- |", *rows]))
    rows = [f"| {a} | {b} | {c} |" for a, b, c in ex["chitchat"]]
    parts.append("\n".join(["### Chit-chat replies (cf. §4.2)", "",
                            "| Chit-chat reply | To negative | To positive |",
                            "| --- | --- | --- |", *rows]))
    return "\n\n".join(parts) + "\n"


def format_summary(result: dict[str, Any]) -> str:
    """A few plain-text lines with the headline numbers."""
    lines = [f"split {result['split']}: {result['sentences']} sentences, "
             f"beam {result['beam_size']}",
             f"transfer accuracy   {result['accuracy'] * 100:6.2f} %",
             f"self-BLEU           {result['self_bleu']:6.2f}",
             f"perplexity          {result['perplexity']:6.1f} "
             f"(sources: {result['source_perplexity']:.1f})",
             f"classifier accuracy {result['classifier_accuracy'] * 100:6.2f} %",
             f"one sentence        {result['ms_per_sentence']:6.1f} ms"]
    for name in DIRECTIONS:
        d = result[name]
        lines.append(f"{name:22s} accuracy {d['accuracy'] * 100:6.2f} %, "
                     f"self-BLEU {d['self_bleu']:6.2f}")
    return "\n".join(lines)
