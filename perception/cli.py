"""`companion data detector`: render the person-and-face detector's data set."""

from __future__ import annotations

import argparse
from pathlib import Path


def add_data(sub: argparse._SubParsersAction) -> None:
    """Register ``data detector``."""
    p = sub.add_parser("detector", help="render the person-and-face YOLO data set",
                       description="Render labelled frames from the robot's head camera in "
                       "randomised households: images/, labels/ (YOLO), data.yaml and "
                       "examples/ with boxes drawn, in --out. Resumable.")
    p.add_argument("--out", type=Path, required=True, help="data set folder")
    p.add_argument("--train", type=int, help="train frames (default from the config)")
    p.add_argument("--val", type=int, help="validation frames")
    p.add_argument("--test", type=int, help="test frames")
    p.add_argument("--seed", type=int, help="base seed (default from the config)")
    p.add_argument("--config", type=Path, help="YAML overriding app/defaults/detector.yaml")
    p.add_argument("--no-progress", action="store_true", help="hide the progress bar")
    p.set_defaults(func=run_data)


def run_data(args: argparse.Namespace) -> int:
    """Render the data set described by the config and the command-line overrides."""
    from tqdm import tqdm

    from perception.detector_config import load_detector_config
    from perception.detector_data import write_dataset

    cfg = load_detector_config(args.config).data
    splits = {k: v for k in ("train", "val", "test")
              if (v := getattr(args, k)) is not None}
    for name, value in splits.items():
        if value < 0:
            raise argparse.ArgumentTypeError(f"--{name} must be >= 0")
    update: dict = {"splits": cfg.splits.model_copy(update=splits)}
    if args.seed is not None:
        update["seed"] = args.seed
    cfg = cfg.model_copy(update=update)
    total = cfg.splits.train + cfg.splits.val + cfg.splits.test
    with tqdm(total=total, unit="frame", disable=args.no_progress) as bar:
        done = write_dataset(args.out, cfg, bar.update)
    print(f"rendered {sum(done.values())} of {total} frames into {args.out} "
          f"({', '.join(f'{k} {v}' for k, v in done.items())})")
    return 0
