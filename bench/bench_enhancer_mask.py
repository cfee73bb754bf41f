"""The power the voice enhancer's mask is raised to (``model.mask_power`` in
config/speech.yaml), chosen on lines that neither the language model, the acoustic
model's adaptation, the enhancer nor ``companion eval asr`` ever saw: the held-out
knowledge questions (``dialogue/data/knowledge_questions.tsv``).

Each question is said by four of the people's voices in the evaluation's living room with
the TV on at 1 and 3 m and, to see that a quiet room loses nothing, quiet at 3 m. For each
power the table gives the word error rate and the share of transcripts the router sends
where it sends the text; the shipped power is the one of least mean word error rate over
the three conditions. A power above 1 takes a cell the net is unsure of down further: the
TV's voice, which the mask leaves partly in, is taken further out.

With ``--lines requests`` the lines are the 90 spoken requests of
``dialogue/data/speech_dev.tsv`` instead, written like what people ask the robot (time,
weather, songs, chit-chat) and, like the questions, learnt by no model and never said by
``companion eval asr``. With ``--unseen-voices`` the lines are said by the four visitors'
voices of ``companion eval asr --voices visitors`` instead, quiet and with the TV on at 1 m.

Usage: python bench/bench_enhancer_mask.py [--limit N] [--powers P ...] [--config SPEECH_YAML]
       [--lines questions|requests] [--unseen-voices] [--microphones one|array]
       [--json PATH]
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import jiwer
import numpy as np

from dialogue.intent import IntentClassifier
from dialogue.speech.config import load_speech_config
from dialogue.speech.recognizer import SpeechRecognizer
from dialogue.speech.training.corpus import tuning_lines
from dialogue.speech.training.evaluate import ROOM_M, VISITOR_VOICES, VOICES, heads_microphones
from dialogue.speech.training.rooms import living_room, recording, speaker_at
from dialogue.speech.words import spoken_words
from robot.audio import RATE
from robot.voices import PEOPLE_VOICES, synthesise
from sim.soundscape import noise_loops

CONDITIONS = (("tv", 1.0), ("tv", 3.0), ("quiet", 3.0))
VISITOR_CONDITIONS = (("quiet", 1.0), ("tv", 1.0))


def main() -> None:
    """Print a row per power."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--limit", type=int, default=None,
                    help="the first N lines (default: 60 questions, all requests)")
    ap.add_argument("--powers", type=float, nargs="+",
                    default=[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 8.0, 12.0])
    ap.add_argument("--config", type=Path, help="speech YAML choosing the models")
    ap.add_argument("--json", type=Path, help="also write the rows here")
    ap.add_argument("--lines", choices=("questions", "requests"), default="questions",
                    help="the held-out knowledge questions, or the spoken requests written "
                         "for choosing settings (dialogue/data/speech_dev.tsv)")
    ap.add_argument("--unseen-voices", action="store_true",
                    help="say the questions in the four visitors' voices of eval asr "
                         "--unseen-voices, quiet and with the TV at 1 m (what the power "
                         "costs a voice the enhancer never learnt)")
    ap.add_argument("--microphones", choices=("one", "array"), default=None,
                    help="one microphone or the head's four, as in eval asr (default: as "
                         "robot.yaml's microphones.array says)")
    args = ap.parse_args()
    array = heads_microphones(args.microphones)
    texts = tuning_lines(args.lines)
    texts = texts[:args.limit or (60 if args.lines == "questions" else len(texts))]
    refs = [" ".join(spoken_words(t)) for t in texts]
    cfg = load_speech_config(args.config)   # each power in every room, loud or quiet
    cfg = cfg.model_copy(update={"model": cfg.model.model_copy(update={"loud_room_db": None})})
    router, recogniser = IntentClassifier.default(), SpeechRecognizer(cfg)
    routes = [router.classify(t).label for t in texts]
    speakers = VISITOR_VOICES if args.unseen_voices else PEOPLE_VOICES[:VOICES]
    voices = [synthesise(t, speakers[i % len(speakers)]) for i, t in enumerate(texts)]
    recordings = {}
    for noise, distance in VISITOR_CONDITIONS if args.unseen_voices else CONDITIONS:
        rng = np.random.default_rng(2)
        room, robot = living_room(*ROOM_M, noise)
        recordings[noise, distance] = [
            recording(room, *v, speaker_at(robot, distance, rng), robot, noise_loops(2), rng,
                      array)
            for v in voices]
    assert recogniser.enhancer is not None, "the speech settings name no enhancer"
    rows = []
    for power in args.powers:
        recogniser.enhancer.power = power
        row: dict[str, object] = {"power": power}
        for (noise, distance), heard in recordings.items():
            hyps = [recogniser.transcribe(audio, RATE).text for audio in heard]
            key = f"{noise}_{distance:g}m"
            row[f"{key}_wer"] = round(jiwer.wer(refs, [h or "-" for h in hyps]), 3)
            row[f"{key}_routing"] = round(float(np.mean(
                [router.classify(h).label == r for h, r in zip(hyps, routes, strict=True)])), 3)
        rows.append(row)
        print(row, flush=True)
    if args.json:
        args.json.write_text(json.dumps(rows, indent=2) + "\n")


if __name__ == "__main__":
    main()
