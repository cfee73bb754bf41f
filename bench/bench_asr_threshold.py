"""The recogniser's confidence threshold (``min_confidence`` in app/defaults/speech.yaml),
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

Usage: python bench/bench_asr_threshold.py [--limit N] [--json PATH] [--config SPEECH_YAML]
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from app.sim.voices import PEOPLE_VOICES
from dialogue.intent import IntentClassifier
from dialogue.qa.text import STOPWORDS
from dialogue.speech.config import load_speech_config
from dialogue.speech.recognizer import SpeechRecognizer
from dialogue.speech.training.corpus import knowledge_questions
from dialogue.speech.training.evaluate import VOICES, said_in_rooms
from dialogue.speech.words import spoken_words

THRESHOLDS = np.round(np.arange(0.0, 0.501, 0.025), 3)
ASK_COST = 0.5   # asking again costs half a wrong answer: the person repeats, once


def content(text: str) -> set[str]:
    """The words of ``text`` as said, function words apart."""
    return {w for w in spoken_words(text) if w not in STOPWORDS}


def main() -> None:
    """Print the table and the chosen threshold."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--limit", type=int, help="only the first N questions")
    ap.add_argument("--json", type=Path, help="also write the rows here")
    ap.add_argument("--config", type=Path, help="speech YAML choosing the models")
    args = ap.parse_args()
    texts = knowledge_questions()[:args.limit]
    router = IntentClassifier.default()
    recogniser = SpeechRecognizer(load_speech_config(args.config))
    routes = [router.classify(t).label for t in texts]
    seen = []   # (near and quiet, confidence, usable)
    for said in said_in_rooms(texts, PEOPLE_VOICES[:VOICES], recogniser, seed=1):
        text, heard = texts[said.index], said.heard
        want = content(text)
        kept = len(want & set(heard.text.split())) / len(want) if want else 1.0
        usable = router.classify(heard.text).label == routes[said.index] and kept >= 0.5
        near = said.noise == "quiet" and said.distance <= 3.0
        seen.append((near, heard.confidence if heard.words else 0.0, usable))
    near, conf, usable = (np.array(c) for c in zip(*seen, strict=True))
    rows = []
    for t in THRESHOLDS:
        row = {"threshold": float(t)}
        for name, where in (("near_quiet", near), ("all", np.ones_like(near))):
            accepted = where & (conf >= t)
            row[f"{name}_accepted"] = round(float(accepted.sum() / where.sum()), 3)
            row[f"{name}_usable"] = (round(float(usable[accepted].mean()), 3)
                                     if accepted.any() else None)
            worth = (np.where(usable, 1.0, -1.0) * accepted - ASK_COST * (where & ~accepted))
            row[f"{name}_worth"] = round(float(worth[where].mean()), 3)
        rows.append(row)
        print(row)
    chosen = max(rows, key=lambda r: r["near_quiet_worth"])["threshold"]
    print(f"{len(texts)} questions; usable without a threshold: near and quiet "
          f"{usable[near].mean():.3f}, all {usable.mean():.3f}; chosen threshold: {chosen}")
    if args.json:
        args.json.write_text(json.dumps({"rows": rows, "chosen": chosen}, indent=1) + "\n")


if __name__ == "__main__":
    main()
