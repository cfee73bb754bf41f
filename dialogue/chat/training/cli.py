"""Command line of the chit-chat bot: ``companion train chat``, ``companion eval chat`` and
``chat_metrics`` (merged into ``companion eval dialogue``).

Handlers import their heavy modules when called, so that ``companion --help`` stays fast.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

from core.interrupts import training_command
from dialogue.chat.config import DEFAULT_CHAT_MODEL

PERPLEXITY_RATIO_BAR = 3.0
LATENCY_BAR_MS = 100.0
SIZE_BAR_MB = 25.0
GENERIC_BAR = 0.10     # share of generic replies of the ranking, at most
DISTINCT_2_BAR = 0.4   # of the ranking, at least
METRIC_KEYS = ("chat_perplexity", "unigram_perplexity", "distinct_1", "distinct_2",
               "latency_ms_median")


def add_train(sub: argparse._SubParsersAction) -> None:
    """Register ``train chat``."""
    p = sub.add_parser("chat", help="train the seq2seq chit-chat bot (LSTM with attention)",
                       description="Train the chit-chat encoder-decoder on Papaya and the "
                       "English chatterbot corpus. Writes checkpoint.pt (resumable), "
                       "train_log.csv, eval_log.csv, data_counts.json and chat.pt (best "
                       "validation perplexity) into --out.")
    p.add_argument("--config", type=Path, help="chat YAML overriding config/chat.yaml")
    p.add_argument("--out", type=Path, default=Path("runs/train-chat"), help="run folder")
    p.add_argument("--resume", action="store_true", help="continue the checkpoint in --out "
                   "with the run's own resolved_config.yaml")
    p.add_argument("--export", type=Path,
                   help="also copy the best model here (e.g. assets/models/chat.pt)")
    p.add_argument("--no-progress", action="store_true", help="hide the progress bar")
    p.set_defaults(func=run_train)
    p = sub.add_parser("chat-pool", help="rebuild the retrieval pool beside a chit-chat model",
                       description="Write where MODEL's training pairs lie in the data (rebuilt "
                       "from the data config stored in it) to the retrieval pool beside it "
                       "(chat.pool.jsonl): references and hashes, not the text.")
    p.add_argument("--model", type=Path, default=DEFAULT_CHAT_MODEL, help="model file")
    p.set_defaults(func=run_pool)


def add_eval(sub: argparse._SubParsersAction) -> None:
    """Register ``eval chat`` (the stand-alone entry; ``eval dialogue`` merges the metrics)."""
    p = sub.add_parser("chat", help="held-out perplexity, baseline, generic share, distinct-n, "
                       "relevance and latency, for beam search alone and for the ranking")
    p.add_argument("--model", type=Path, default=DEFAULT_CHAT_MODEL, help="model file")
    p.add_argument("--examples", type=int, default=12, help="test exchanges in the table")
    p.add_argument("--no-relevance", action="store_true",
                   help="skip the sentence-embedding relevance (no MiniLM model needed)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=run_eval)


@training_command("chat")
def run_train(args: argparse.Namespace) -> int:
    """Handler of ``companion train chat``."""
    from core.run_config import config_for
    from dialogue.chat.config import ChatConfig, load_chat_config
    from dialogue.chat.training.train import MODEL_FILE, train

    cfg = config_for(args, ChatConfig, lambda: load_chat_config(args.config), "config")
    summary = train(cfg, args.out, resume=args.resume,
                    progress=not getattr(args, "no_progress", False))
    if args.export:
        from core.checkpoint import atomic_copy
        from dialogue.chat.pool import pool_path

        atomic_copy(args.out / MODEL_FILE, args.export)
        atomic_copy(pool_path(args.out / MODEL_FILE), pool_path(args.export))
        summary["exported"] = str(args.export)
    print(json.dumps(summary, indent=2))
    return 0


def run_pool(args: argparse.Namespace) -> int:
    """Handler of ``companion train chat-pool``: the pool of the model's training split."""
    from dialogue.chat.config import ChatDataConfig
    from dialogue.chat.model import read_chat_file
    from dialogue.chat.pool import pool_path, write_pool
    from dialogue.chat.training.data import load_chat_data

    data_cfg = read_chat_file(args.model)["config"]["data"]
    data = load_chat_data(ChatDataConfig(**data_cfg))
    write_pool(pool_path(args.model), data.splits["train"], data.refs["train"], data_cfg)
    print(f"{pool_path(args.model)}: {len(data.splits['train'])} training pairs")
    return 0


def chat_metrics(model_path: str | Path = DEFAULT_CHAT_MODEL, relevance: bool = False,
                 n_examples: int = 12) -> dict[str, Any]:
    """The chit-chat metrics (``companion eval dialogue`` merges some): the five
    ``METRIC_KEYS`` of the ranked replies, ``generic_share``, ``decodings`` (the figures of
    beam search alone and of the ranking), ``perplexity_ratio``, ``model_mb``,
    ``test_pairs``, ``examples`` and ``meets_bars``; with ``relevance`` also each decoding's
    and the references' mean MiniLM relevance.

    Raises :class:`~dialogue.chat.model.ChatModelError` (a ``UserError``) for a missing or
    corrupt file and ``ChatDataError`` when the data behind its test split is missing.
    """
    from dialogue.chat.training.evaluate import evaluate_file

    result = evaluate_file(model_path, n_examples, relevance)
    d = result["decodings"]
    result["meets_bars"] = {
        "perplexity_ratio": result["perplexity_ratio"] >= PERPLEXITY_RATIO_BAR,
        "latency_ms_median": result["latency_ms_median"] <= LATENCY_BAR_MS,
        "model_mb": result["model_mb"] <= SIZE_BAR_MB,
        "generic_share": result["generic_share"] <= GENERIC_BAR,
        "distinct_2": result["distinct_2"] >= DISTINCT_2_BAR}
    if relevance:
        result["meets_bars"]["relevance"] = d["ranked"]["relevance"] > d["beam"]["relevance"]
    return result


def run_eval(args: argparse.Namespace) -> int:
    """Handler of ``eval chat``: print the metrics (``--json``: one object)."""
    r = chat_metrics(args.model, not args.no_relevance, args.examples)
    if args.json:
        print(json.dumps({k: v for k, v in r.items() if k != "examples_markdown"}))
        return 0
    ok = {k: "meets" if v else "BELOW" for k, v in r["meets_bars"].items()}
    print(f"chit-chat perplexity (held out, {r['test_pairs']} pairs): "
          f"{r['chat_perplexity']:.2f}; unigram baseline {r['unigram_perplexity']:.2f}; "
          f"ratio {r['perplexity_ratio']:.2f} ({ok['perplexity_ratio']} the bar of "
          f"{PERPLEXITY_RATIO_BAR:g}x)")
    for name, d in r["decodings"].items():
        rel = f", relevance {d['relevance']:.3f}" if "relevance" in d else ""
        print(f"{name:>6}: generic {d['generic_share']:.3f}, distinct-1 {d['distinct_1']:.3f}, "
              f"distinct-2 {d['distinct_2']:.3f}{rel}, latency median "
              f"{d['latency_ms_median']:.1f} ms")
    if "reference_relevance" in r:
        beats = "beats" if r["meets_bars"]["relevance"] else "does NOT beat"
        print(f"reference replies: relevance {r['reference_relevance']:.3f} (the ceiling); "
              f"the ranking {beats} beam search alone")
    print(f"ranked: generic {ok['generic_share']} the bar of {GENERIC_BAR:g}, distinct-2 "
          f"{ok['distinct_2']} the bar of {DISTINCT_2_BAR:g}, latency "
          f"{ok['latency_ms_median']} the bar of {LATENCY_BAR_MS:g} ms")
    print(f"model file: {r['model_mb']:.1f} MB ({ok['model_mb']} the bar of "
          f"{SIZE_BAR_MB:g} MB)\n")
    print(r["examples_markdown"])
    return 0

