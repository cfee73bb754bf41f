"""The recogniser's confidence threshold (config/speech.yaml: ``min_confidence`` for
pocketsphinx, ``model.whisper.min_confidence`` for Whisper),
chosen on lines that neither the language model, the acoustic model's adaptation nor
``companion eval asr`` ever saw: the held-out knowledge questions
(``dialogue/data/knowledge_questions.tsv``, "what is a volcano", "who invented the
telephone").

Each question is said by four of the people's voices in the evaluation's living room
(quiet and with the TV on, 1, 3 and 5 m; ``said_in_rooms``). A transcript is *usable* when
the router sends it where it sends the text and it keeps at least half of the text's
content words: acting on it gives a fitting answer. For each threshold the table gives the
share of transcripts accepted and the share of accepted ones that are usable, in a quiet
room within 3 m (where people talk to a robot) and over all six conditions, and the worth of
the threshold there: a usable transcript acted on counts +1, an unusable one acted on -1 (a
wrong answer), a line asked for again -``ASK_COST``. It prints the threshold of most worth
within 3 m of a quiet room (docs/BENCHMARKS.md says how the shipped one was read from the
table). (The rule before the acoustic model was adapted, the
smallest threshold with 90 % of the accepted transcripts usable, chooses nothing on these
lines: confidence does not separate them that well.)

The ``faint_`` columns ask whether a *faint* line, one whose speech stood less than
``listening.closer_below_snr_db`` (config/behaviour.yaml) over the noise at the
microphones, in any of the six conditions, is worth holding to a stricter threshold than the
rest: under it the robot asks its speaker to come closer, which counts -``ASK_COST`` like
asking again. Thresholds below the decoder's own are not weighed for them (that one holds for
every line); it prints the one of most worth.

With ``--lines requests`` the lines are the 90 spoken requests (``dialogue/data/
speech_dev.tsv``) instead; ``--microphones`` records one microphone or the head's four, as
in ``companion eval asr`` (default: as robot.yaml's ``microphones.array`` says).

Usage: python bench/bench_asr_threshold.py [--limit N] [--json PATH] [--config SPEECH_YAML]
       [--lines questions|requests] [--microphones one|array]
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from behaviours.config import load_behaviour_config
from dialogue.intent import IntentClassifier
from dialogue.qa.text import STOPWORDS
from dialogue.speech.config import load_speech_config
from dialogue.speech.recognizer import SpeechRecognizer
from dialogue.speech.training.corpus import tuning_lines
from dialogue.speech.training.evaluate import VOICES, heads_microphones, said_in_rooms
from dialogue.speech.words import spoken_words
from robot.voices import PEOPLE_VOICES

THRESHOLDS = np.round(np.arange(0.0, 0.951, 0.025), 3)   # whisper's confidences run higher
ASK_COST = 0.5   # asking again costs half a wrong answer: the person repeats, once


def content(text: str) -> set[str]:
    """The words of ``text`` as said, function words apart."""
    return {w for w in spoken_words(text) if w not in STOPWORDS}


def weighed(name: str, where: np.ndarray, accepted: np.ndarray,
            usable: np.ndarray) -> dict[str, float | None]:
    """Of the transcripts ``where`` selects: the share ``accepted``, the share of those
    usable, and the mean worth of acting on the accepted and asking for the rest again."""
    taken = where & accepted
    worth = np.where(usable, 1.0, -1.0) * taken - ASK_COST * (where & ~accepted)
    return {f"{name}_n": int(where.sum()),
            f"{name}_accepted": round(float(taken.sum() / max(where.sum(), 1)), 3),
            f"{name}_usable": round(float(usable[taken].mean()), 3) if taken.any() else None,
            f"{name}_worth": round(float(worth[where].mean()), 3) if where.any() else None}


def main() -> None:
    """Print the tables and the chosen thresholds."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--limit", type=int, help="only the first N lines")
    ap.add_argument("--json", type=Path, help="also write the rows here")
    ap.add_argument("--config", type=Path, help="speech YAML choosing the models")
    ap.add_argument("--lines", choices=("questions", "requests"), default="questions",
                    help="the held-out knowledge questions, or the spoken requests")
    ap.add_argument("--microphones", choices=("one", "array"), default=None,
                    help="one microphone or the head's four (default: as robot.yaml says)")
    args = ap.parse_args()
    array = heads_microphones(args.microphones)
    texts = tuning_lines(args.lines)[:args.limit]
    router, cfg = IntentClassifier.default(), load_speech_config(args.config)
    recogniser = SpeechRecognizer(cfg)
    routes = [router.classify(t).label for t in texts]
    seen = []   # (near and quiet, confidence, usable, SNR at the microphones)
    for said in said_in_rooms(texts, PEOPLE_VOICES[:VOICES], recogniser, seed=1, array=array):
        text, heard = texts[said.index], said.heard
        want = content(text)
        kept = len(want & set(heard.text.split())) / len(want) if want else 1.0
        usable = router.classify(heard.text).label == routes[said.index] and kept >= 0.5
        near = said.noise == "quiet" and said.distance <= 3.0
        seen.append((near, heard.confidence if heard.words else 0.0, usable, heard.snr_db))
    near, conf, usable, snr = (np.array(c) for c in zip(*seen, strict=True))
    faint = snr < load_behaviour_config().listening.closer_below_snr_db
    rows = []
    for t in THRESHOLDS:
        accepted = conf >= t
        rows.append({"threshold": float(t), **weighed("near_quiet", near, accepted, usable),
                     **weighed("all", np.ones_like(near), accepted, usable),
                     **weighed("faint", faint, accepted, usable)})
        print(rows[-1])
    chosen = max(rows, key=lambda r: r["near_quiet_worth"])["threshold"]
    for_faint = [r for r in rows if r["threshold"] >= cfg.acting_confidence and faint.any()]
    faint_chosen = (max(for_faint, key=lambda r: r["faint_worth"])["threshold"]
                    if for_faint else None)
    print(f"{len(texts)} lines; usable without a threshold: near and quiet "
          f"{usable[near].mean():.3f}, all {usable.mean():.3f}, faint "
          f"{usable[faint].mean() if faint.any() else float('nan'):.3f} ({faint.sum()}); "
          f"chosen threshold: {chosen}; for a faint line: {faint_chosen}")
    if args.json:
        args.json.write_text(json.dumps({"rows": rows, "chosen": chosen,
                                         "faint_chosen": faint_chosen}, indent=1) + "\n")


if __name__ == "__main__":
    main()
