"""Command line of the chit-chat bot: ``companion train chat``, ``companion eval chat`` and
``chat_metrics`` (merged into ``companion eval dialogue``).

Handlers import their heavy modules when called, so that ``companion --help`` stays fast.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

from app.core.interrupts import training_command
from dialogue.chat.config import DEFAULT_CHAT_MODEL

PERPLEXITY_RATIO_BAR = 3.0
LATENCY_BAR_MS = 100.0
SIZE_BAR_MB = 25.0
METRIC_KEYS = ("chat_perplexity", "unigram_perplexity", "distinct_1", "distinct_2",
               "latency_ms_median")


def add_train(sub: argparse._SubParsersAction) -> None:
    """Register ``train chat``."""
    p = sub.add_parser("chat", help="train the seq2seq chit-chat bot (LSTM with attention)",
                       description="Train the chit-chat encoder-decoder on Papaya and the "
                       "English chatterbot corpus. Writes checkpoint.pt (resumable), "
                       "train_log.csv, eval_log.csv, data_counts.json and chat.pt (best "
                       "validation perplexity) into --out.")
    p.add_argument("--config", type=Path, help="chat YAML overriding app/defaults/chat.yaml")
    p.add_argument("--out", type=Path, default=Path("runs/train-chat"), help="run folder")
    p.add_argument("--resume", action="store_true", help="continue the checkpoint in --out "
                   "with the run's own resolved_config.yaml")
    p.add_argument("--export", type=Path,
                   help="also copy the best model here (e.g. assets/models/chat.pt)")
    p.add_argument("--no-progress", action="store_true", help="hide the progress bar")
    p.set_defaults(func=run_train)


def add_eval(sub: argparse._SubParsersAction) -> None:
    """Register ``eval chat`` (the stand-alone entry; ``eval dialogue`` merges the metrics)."""
    p = sub.add_parser("chat", help="held-out perplexity, baseline, distinct-n and latency")
    p.add_argument("--model", type=Path, default=DEFAULT_CHAT_MODEL, help="model file")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=run_eval)


@training_command("chat")
def run_train(args: argparse.Namespace) -> int:
    """Handler of ``companion train chat``."""
    from app.core.run_config import config_for
    from dialogue.chat.config import ChatConfig, load_chat_config
    from dialogue.chat.training.train import MODEL_FILE, train

    cfg = config_for(args, ChatConfig, lambda: load_chat_config(args.config), "config")
    summary = train(cfg, args.out, resume=args.resume,
                    progress=not getattr(args, "no_progress", False))
    if args.export:
        from app.core.checkpoint import atomic_copy

        atomic_copy(args.out / MODEL_FILE, args.export)
        summary["exported"] = str(args.export)
    print(json.dumps(summary, indent=2))
    return 0


def chat_metrics(model_path: str | Path = DEFAULT_CHAT_MODEL) -> dict[str, Any]:
    """The chit-chat metrics for ``companion eval dialogue``: the five ``METRIC_KEYS`` plus
    ``perplexity_ratio``, ``model_mb``, ``test_pairs``, ``examples`` and ``meets_bars``.

    Raises :class:`~dialogue.chat.model.ChatModelError` (a ``UserError``) for a missing or
    corrupt file and ``ChatDataError`` when the data behind its test split is missing.
    """
    from dialogue.chat.training.evaluate import evaluate_file

    result = evaluate_file(model_path)
    result["meets_bars"] = {
        "perplexity_ratio": result["perplexity_ratio"] >= PERPLEXITY_RATIO_BAR,
        "latency_ms_median": result["latency_ms_median"] <= LATENCY_BAR_MS,
        "model_mb": result["model_mb"] <= SIZE_BAR_MB}
    return result


def run_eval(args: argparse.Namespace) -> int:
    """Handler of ``eval chat``: print the metrics (``--json``: one object)."""
    r = chat_metrics(args.model)
    if args.json:
        print(json.dumps({k: v for k, v in r.items() if k != "examples_markdown"}))
        return 0
    ok = {k: "meets" if v else "BELOW" for k, v in r["meets_bars"].items()}
    print(f"chit-chat perplexity (held out, {r['test_pairs']} pairs): "
          f"{r['chat_perplexity']:.2f}; unigram baseline {r['unigram_perplexity']:.2f}; "
          f"ratio {r['perplexity_ratio']:.2f} ({ok['perplexity_ratio']} the bar of "
          f"{PERPLEXITY_RATIO_BAR:g}x)")
    print(f"distinct-1 {r['distinct_1']:.3f}, distinct-2 {r['distinct_2']:.3f}")
    print(f"reply latency: median {r['latency_ms_median']:.1f} ms "
          f"({ok['latency_ms_median']} the bar of {LATENCY_BAR_MS:g} ms)")
    print(f"model file: {r['model_mb']:.1f} MB ({ok['model_mb']} the bar of "
          f"{SIZE_BAR_MB:g} MB)\n")
    print(r["examples_markdown"])
    return 0

