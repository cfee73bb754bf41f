"""`companion data detector`: render the person-and-face detector's data set.

Handlers import their heavy modules when called, so that ``companion --help`` stays fast.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from core.cli_args import integer, real, seed


def add_data(sub: argparse._SubParsersAction) -> None:
    """Register ``data detector``."""
    p = sub.add_parser("detector", help="render the person-and-face YOLO data set",
                       description="Render labelled frames from the robot's head camera in "
                       "randomised households: images/, labels/ (YOLO), data.yaml and "
                       "examples/ with boxes drawn, in --out. Resumable.")
    p.add_argument("--out", type=Path, required=True, help="data set folder")
    p.add_argument("--train", type=integer(0, 1_000_000),
                   help="train frames (default from the config)")
    p.add_argument("--val", type=integer(0, 1_000_000), help="validation frames")
    p.add_argument("--test", type=integer(0, 1_000_000), help="test frames")
    p.add_argument("--seed", type=seed(), help="base seed (default from the config)")
    p.add_argument("--config", type=Path, help="YAML overriding config/detector.yaml")
    p.add_argument("--no-progress", action="store_true", help="hide the progress bar")
    p.set_defaults(func=run_data)


def run_data(args: argparse.Namespace) -> int:
    """Render the data set described by the config and the command-line overrides."""
    from tqdm import tqdm

    from perception.detector.config import load_detector_config
    from perception.detector.training.data import write_dataset

    cfg = load_detector_config(args.config).data
    splits = {k: v for k in ("train", "val", "test")
              if (v := getattr(args, k)) is not None}
    update: dict = {"splits": cfg.splits.model_copy(update=splits)}
    if args.seed is not None:
        update["seed"] = args.seed
    cfg = cfg.model_copy(update=update)
    total = cfg.splits.train + cfg.splits.val + cfg.splits.test
    with tqdm(total=total, unit="frame", disable=True if args.no_progress else None) as bar:
        done = write_dataset(args.out, cfg, bar.update)
    print(f"rendered {sum(done.values())} of {total} frames into {args.out} "
          f"({', '.join(f'{k} {v}' for k, v in done.items())})")
    return 0


def add_train(sub: argparse._SubParsersAction) -> None:
    """Register ``train detector``."""
    p = sub.add_parser("detector", help="train the person-and-face YOLO detector",
                       description="Train ultralytics YOLO from its model yaml (no pretrained "
                       "weights) on a data set from `companion data detector`, on the CPU. "
                       "The run folder keeps weights/last.pt after every epoch (--resume).")
    p.add_argument("--data", type=Path, default=Path("runs/detector-data"),
                   help="data set folder (or its data.yaml)")
    p.add_argument("--out", type=Path, default=Path("runs/train-detector"), help="run folder")
    p.add_argument("--config", type=Path, help="YAML overriding config/detector.yaml")
    p.add_argument("--epochs", type=integer(1, 10_000), help="override train.epochs")
    p.add_argument("--resume", action="store_true", help="continue the run in --out")
    p.add_argument("--export", type=Path,
                   help="copy the best weights here (e.g. assets/models/detector.pt) and "
                   "their ONNX export beside them (detector.onnx)")
    p.set_defaults(func=run_train)


def run_train(args: argparse.Namespace) -> int:
    """Handler of ``companion train detector``."""
    from perception.detector.config import load_detector_config
    from perception.detector.training.train import train_detector

    cfg = load_detector_config(args.config).train
    if args.epochs is not None:
        cfg = cfg.model_copy(update={"epochs": args.epochs})
    best = train_detector(cfg, args.data, args.out, resume=args.resume, export=args.export)
    print(f"best weights: {best}" + (f" (copied to {args.export})" if args.export else ""))
    return 0


def add_export(sub: argparse._SubParsersAction) -> None:
    """Register ``export detector``."""
    from perception.detector.config import DEFAULT_DETECTOR, DEFAULT_TRAINED

    p = sub.add_parser("detector", help="export YOLO weights to the ONNX file the robot runs",
                       description="Export ultralytics YOLO weights to an ONNX graph with the "
                       "head camera's input size, run by onnxruntime on the robot.")
    p.add_argument("--weights", type=Path, default=DEFAULT_TRAINED,
                   help="ultralytics weights (default: the shipped detector.pt)")
    p.add_argument("--out", type=Path, default=DEFAULT_DETECTOR,
                   help="ONNX file (default: the shipped detector.onnx)")
    p.add_argument("--imgsz", type=integer(32, 4096),
                   help="longer input side in pixels (default: detect.imgsz of the config)")
    p.set_defaults(func=run_export)


def run_export(args: argparse.Namespace) -> int:
    """Handler of ``companion export detector``."""
    from perception.detector.config import load_detector_config
    from perception.detector.training.train import export_onnx

    export_onnx(args.weights, args.out, args.imgsz or load_detector_config().detect.imgsz)
    print(f"exported {args.weights} to {args.out}")
    return 0


def add_eval(sub: argparse._SubParsersAction) -> None:
    """Register ``eval detector``."""
    p = sub.add_parser("detector", help="mAP and CPU latency of the detector",
                       description="Person and face mAP on a held-out split of a rendered "
                       "data set and the median CPU latency of one 320x240 frame (100 calls).")
    p.add_argument("--weights", type=Path, help="YOLO weights (default: the shipped detector)")
    p.add_argument("--data", type=Path, default=Path("runs/detector-data"),
                   help="data set folder (or its data.yaml)")
    p.add_argument("--split", default="test", choices=("train", "val", "test"))
    p.add_argument("--iou", type=real(above=0, below=1),
                   help="NMS overlap, 0 < IOU < 1 (default: the robot's detect.iou)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--out", type=Path, help="also write the figures to this JSON file")
    p.set_defaults(func=run_eval)


def run_eval(args: argparse.Namespace) -> int:
    """Handler of ``companion eval detector``."""
    import json

    from perception.detector.training.train import evaluate_detector, write_json

    figures = evaluate_detector(args.weights, args.data, args.split, iou=args.iou)
    if args.out:
        write_json(figures, args.out)
    if args.json:
        print(json.dumps(figures))
    else:
        for key, value in figures.items():
            print(f"{key:20s} {value:.4f}" if isinstance(value, float) else f"{key:20s} {value}")
    return 0
