"""``companion train mood-lm`` and ``companion eval mood-style``: the mood gate's language
model and the figures of what the robot says in each mood. Handlers import their heavy
modules when called, so that ``companion --help`` stays fast."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from core.cli_args import integer


def add_train(sub: argparse._SubParsersAction) -> None:
    """Register ``train mood-lm``."""
    p = sub.add_parser("mood-lm", help="count the mood gate's bigram language model",
                       description="Count the Kneser-Ney bigram model that the mood gate "
                       "scores fluency with, from the Yelp training split and the robot's "
                       "conversational training lines (config/mood_style.yaml, "
                       "bigram section).")
    p.add_argument("--config", type=Path, help="YAML overriding config/mood_style.yaml")
    p.add_argument("--out", type=Path, help="file to write (default: bigram.npz in the "
                   "config's model_dir)")
    p.set_defaults(func=run_train_lm)


def add_eval(sub: argparse._SubParsersAction) -> None:
    """Register ``eval mood-style``."""
    p = sub.add_parser("mood-style", help="what the robot says in each mood: judge flips, "
                       "fluency and content against the unstyled replies",
                       description="Say held-out robot replies (chit-chat test and validation "
                       "replies, QA answers to held-out questions) in both moods through the "
                       "mood gate; report per mood the judge's flip rate, the perplexity "
                       "ratio, the content words kept and the share said by the model, by the "
                       "fallback and unchanged.")
    p.add_argument("--config", type=Path, help="YAML overriding config/mood_style.yaml")
    p.add_argument("--limit", type=integer(1, 100_000), default=500,
                   help="held-out lines to say (default 500)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--out", type=Path, default=Path("runs/eval-mood-style"),
                   help="folder for metrics.json and examples.md")
    p.set_defaults(func=run_eval_mood)


def run_train_lm(args: argparse.Namespace) -> int:
    """Handler of ``companion train mood-lm``."""
    from dialogue.style.mood_config import BIGRAM_FILE, load_mood_config
    from dialogue.style.training.mood_lm import train_bigram

    cfg = load_mood_config(args.config)
    out = args.out or cfg.resolved_model_dir() / BIGRAM_FILE
    print(json.dumps(train_bigram(cfg, out), indent=2))
    return 0


def run_eval_mood(args: argparse.Namespace) -> int:
    """Handler of ``companion eval mood-style``; exit status 0 also when a bar is missed
    (the figures say so)."""
    from dialogue.style.mood import MoodStyler
    from dialogue.style.mood_config import load_mood_config
    from dialogue.style.training.mood_eval import evaluate_mood, examples_table, format_mood

    result = evaluate_mood(MoodStyler.load(load_mood_config(args.config)), args.limit)
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "metrics.json").write_text(json.dumps(result, indent=2))
    (args.out / "examples.md").write_text(examples_table(result))
    if args.json:
        print(json.dumps({k: v for k, v in result.items() if k != "examples"}))
    else:
        print(format_mood(result))
        print(f"\nmetrics.json and examples.md in {args.out}")
    return 0
