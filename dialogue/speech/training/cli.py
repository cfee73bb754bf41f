"""Command line of speech recognition: ``companion train asr`` (the household language
model and the adapted acoustic model) and ``companion eval asr`` (word error rate and
routing by distance and noise).

Handlers import their heavy modules when called, so that ``companion --help`` stays fast.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from core.cli_args import integer, seed
from core.paths import MODELS_DIR

WER_BAR = 0.15          # at 1 m in a quiet room
ROUTING_BAR = 0.90      # at 1 m in a quiet room
TV_ROUTING_BAR = 0.80   # at 3 m with the TV on


def add_train(sub: argparse._SubParsersAction) -> None:
    """Register ``asr`` under ``companion train``."""
    p = sub.add_parser("asr", help="estimate the household language model of the speech "
                                   "recogniser and adapt its acoustic model, from the "
                                   "project's own lines")
    p.add_argument("--config", type=Path, default=None, help="YAML merged over speech.yaml")
    p.add_argument("--out", type=Path, default=MODELS_DIR / "speech",
                   help="folder for household.lm.bin, household.dict, household.json and "
                        "the adapted acoustic model in acoustic/ and enhancer.pt")
    p.add_argument("--only", choices=("language", "acoustic", "enhancer"), default=None,
                   help="make only the language model (seconds), the acoustic model "
                        "(minutes) or the voice enhancer (about two hours)")
    p.set_defaults(func=run_train)


def add_eval(sub: argparse._SubParsersAction) -> None:
    """Register ``asr`` under ``companion eval``."""
    p = sub.add_parser("asr", help="word error rate and routing accuracy of the speech "
                                   "recogniser by distance and noise")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--limit", type=integer(1), default=None,
                   help="only the first N lines of each held-out file (a quick look)")
    p.add_argument("--seed", type=seed(), default=0, help="where the speakers stand")
    p.add_argument("--config", type=Path, default=None,
                   help="YAML merged over speech.yaml (e.g. model: {acoustic_model: null} for "
                        "the wheel's unadapted acoustic model)")
    p.add_argument("--voices", choices=("household", "visitors", "held-out"),
                   default="household",
                   help="who says the lines: four of the household's people (default), four "
                        "espeak-ng visitors no person has, or the held-out synthesizer "
                        "families (Flite, Festival) no model or setting was chosen on")
    p.add_argument("--microphones", choices=("one", "array"), default=None,
                   help="record one microphone (the beam's gain assumed, the TV dry) or each "
                        "of the head's four, decoded as model.beamformer says (default: as "
                        "robot.yaml's microphones.array says)")
    p.add_argument("--recordings", action="store_true",
                   help="people's own recorded voices instead: the human recordings of "
                        "Debian packages, straight in and at 1 and 3 m of a quiet room "
                        "(--limit: per set; docs/speech.md, Human recordings)")
    p.set_defaults(func=run_eval)


def run_train(args: argparse.Namespace) -> int:
    """``companion train asr``."""
    from dialogue.speech.config import load_speech_config
    from dialogue.speech.training.acoustic import (
        adapt_acoustic_model,
        adaptation_beam,
        adaptation_enhancer,
        adaptation_front_end,
        adaptation_lines,
    )
    from dialogue.speech.training.enhancer import train_enhancer
    from dialogue.speech.training.train import (
        evaluation_words,
        full_dictionary,
        train_language_model,
    )

    cfg = load_speech_config(args.config)
    figures: dict[str, object] = {}
    if args.only in (None, "language"):
        figures["language_model"] = train_language_model(cfg, args.out)
    if args.only in (None, "enhancer"):
        lines = adaptation_lines(evaluation_words(), set(full_dictionary()))
        figures["enhancer"] = train_enhancer(cfg.enhance, lines, args.out, progress=print)
    if args.only in (None, "acoustic"):
        figures["acoustic_model"] = adapt_acoustic_model(
            cfg.adapt, evaluation_words(), args.out / "acoustic", adaptation_enhancer(cfg),
            progress=print, beam=adaptation_beam(cfg), front_end=adaptation_front_end(cfg))
    print(json.dumps(figures, indent=2))
    return 0


def run_eval(args: argparse.Namespace) -> int:
    """``companion eval asr``: the table, and whether it meets the bars."""
    from dialogue.speech.config import load_speech_config
    from dialogue.speech.training.evaluate import evaluate_asr, heads_microphones

    if args.recordings:
        from dialogue.speech.training.recordings import evaluate_recordings, report

        found = evaluate_recordings(args.limit, args.seed, load_speech_config(args.config),
                                    heads_microphones(args.microphones))
        print(json.dumps(found) if args.json else "\n".join(report(found)))
        return 0
    result = evaluate_asr(args.limit, args.seed, cfg=load_speech_config(args.config),
                          voices=args.voices,
                          array=heads_microphones(args.microphones))
    if args.json:
        print(json.dumps(result))
        return 0
    print(f"{result['lines']} held-out lines, voices {', '.join(result['voices'])}; "
          f"recognition {result['real_time_factor']:.2f} x real time")
    print(f"{'voices':<10} {'noise':<6} {'distance':>8} {'WER':>6} {'understood':>10} "
          f"{'routing':>8} {'on text':>8}")
    for r in result["rows"]:
        routing = f"{r['routing']:.3f}" if r["routing"] is not None else "-"
        text = f"{r['routing_text']:.3f}" if r["routing_text"] is not None else "-"
        print(f"{r['voices']:<10} {r['noise']:<6} {r['distance_m']:>7g}m {r['wer']:>6.3f} "
              f"{r['understood']:>10.3f} {routing:>8} {text:>8}")
    rows = result["rows"]
    quiet = [r["wer"] for r in rows if r["noise"] == "quiet" and r["distance_m"] == 1]
    near = [r["routing"] for r in rows if r["noise"] == "quiet" and r["distance_m"] == 1]
    tv = [r["routing"] for r in rows if r["noise"] == "tv" and r["distance_m"] == 3]
    print(f"bars: WER at 1 m, quiet, at most {max(quiet):.3f} (bar <= {WER_BAR}); routing at "
          f"1 m quiet at least {min(near):.3f} (bar >= {ROUTING_BAR}), at 3 m with the TV at "
          f"least {min(tv):.3f} (bar >= {TV_ROUTING_BAR})")
    return 0
