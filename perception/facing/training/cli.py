"""``companion data facing``, ``companion train facing`` and ``companion eval facing``.

Handlers import their heavy modules when called, so that ``companion --help`` stays fast.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from core.interrupts import training_command

DEFAULT_DATA = Path("runs/facing-data")


def add_data(sub: argparse._SubParsersAction) -> None:
    """Register ``data facing``."""
    p = sub.add_parser("facing", help="render people and their facing angles",
                       description="Render people from the robot's head camera, crop them by "
                       "their box and label where they look (train/val/test .npz in --out; "
                       "resumable by split).")
    p.add_argument("--out", type=Path, default=DEFAULT_DATA, help="data set folder")
    p.add_argument("--config", type=Path, help="YAML overriding config/facing.yaml")
    p.set_defaults(func=run_data)


def add_train(sub: argparse._SubParsersAction) -> None:
    """Register ``train facing``."""
    p = sub.add_parser("facing", help="train the facing network",
                       description="Train the facing CNN on a `data facing` set; writes "
                       "checkpoint.pt (resumable), train_log.csv, resolved_config.yaml and the "
                       "best validated facing.pt into --out.")
    p.add_argument("--data", type=Path, default=DEFAULT_DATA, help="data set folder")
    p.add_argument("--out", type=Path, default=Path("runs/train-facing"), help="run folder")
    p.add_argument("--config", type=Path, help="YAML overriding config/facing.yaml")
    p.add_argument("--resume", action="store_true", help="continue the checkpoint in --out "
                   "with the run's own resolved_config.yaml")
    p.add_argument("--export", type=Path, help="also copy facing.pt here "
                   "(assets/models/facing.pt)")
    p.set_defaults(func=run_train)


def add_eval(sub: argparse._SubParsersAction) -> None:
    """Register ``eval facing``."""
    p = sub.add_parser("facing", help="angular error and view accuracy of the facing network",
                       description="Score a facing model on the test split of a `data "
                       "facing` set against the bars of config/facing.yaml.")
    p.add_argument("--data", type=Path, default=DEFAULT_DATA, help="data set folder")
    p.add_argument("--model", type=Path, help="facing.pt (default: the shipped one)")
    p.add_argument("--split", choices=["test", "val"], default="test")
    p.add_argument("--config", type=Path, help="YAML overriding config/facing.yaml")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=run_eval)


def run_data(args: argparse.Namespace) -> int:
    """Handler of ``companion data facing``."""
    from perception.facing.config import load_facing_config
    from perception.facing.training.data import write_facing_dataset

    counts = write_facing_dataset(args.out, load_facing_config(args.config).data)
    print(f"crops per split: {counts} in {args.out}")
    return 0


@training_command("facing")
def run_train(args: argparse.Namespace) -> int:
    """Handler of ``companion train facing``."""
    from core.checkpoint import atomic_copy
    from core.run_config import config_for
    from perception.facing.config import FacingConfig, load_facing_config
    from perception.facing.training.train import MODEL_FILE, train

    cfg = config_for(args, FacingConfig, lambda: load_facing_config(args.config), "config")
    summary = train(cfg, args.data, args.out, args.resume)
    if args.export:
        atomic_copy(args.out / MODEL_FILE, args.export)
    print(json.dumps(summary))
    return 0


def run_eval(args: argparse.Namespace) -> int:
    """Handler of ``companion eval facing``."""
    from core.errors import UserError
    from perception.facing.config import DEFAULT_FACING_MODEL, load_facing_config
    from perception.facing.model import FacingEstimator
    from perception.facing.training.data import load_split
    from perception.facing.training.evaluate import bars_met, facing_metrics

    cfg = load_facing_config(args.config)
    model = args.model or DEFAULT_FACING_MODEL
    if not (args.data / f"{args.split}.npz").is_file():
        raise UserError(f"{args.data}: no {args.split}.npz (make it: companion data facing)")
    result = facing_metrics(FacingEstimator.load(model), load_split(args.data, args.split))
    result["pass"] = bars_met(result, cfg.eval.bars)
    result["model"], result["split"] = str(model), args.split
    if args.json:
        print(json.dumps(result))
    else:
        for key in ("mae_deg", "wrong_side_share", "view_accuracy"):
            verdict = (f"  (bar {cfg.eval.bars[key]}: {'pass' if result['pass'][key] else 'FAIL'})"
                       if key in cfg.eval.bars else "")
            print(f"{key:>16}: {result[key]:.3f}{verdict}")
        for pose, m in result.get("by_pose", {}).items():
            print(f"{pose:>16}: MAE {m['mae_deg']:.1f} deg, view {m['view_accuracy']:.3f} "
                  f"({m['crops']} crops)")
    return 0
