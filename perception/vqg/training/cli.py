"""``companion data vqg``, ``companion train vqg``, ``companion eval vqg`` and ``companion ask``.

Heavy modules (torch, the renderer) are imported inside the handlers so that
``companion --help`` stays fast.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from core.cli_args import integer, seed
from core.errors import UserError
from core.files import read_bytes
from core.interrupts import training_command
from core.paths import MODELS_DIR

if TYPE_CHECKING:
    import numpy as np

    from perception.vqg.config import DecodeConfig
    from perception.vqg.generator import Screening

DEFAULT_MODEL = MODELS_DIR / "vqg.pt"
IMAGE_LIMIT = 50 << 20   # bytes: an image for `companion ask`


def add_data(sub: argparse._SubParsersAction) -> None:
    """Register ``data vqg``."""
    p = sub.add_parser("vqg", help="render the visual-question-generation data set",
                       description="Render household frames from the robot's head camera with "
                       "their scene graphs and grounded questions: images/, scenes/, "
                       "questions/{split}.jsonl and meta.json in --out. Resumable.")
    p.add_argument("--out", type=Path, required=True, help="data set folder")
    for split in ("train", "val", "test"):
        p.add_argument(f"--{split}", type=integer(0, 1_000_000),
                       help=f"{split} images (default from the config)")
    p.add_argument("--seed", type=seed(), help="base seed (default from the config)")
    p.add_argument("--no-household", action="store_true",
                   help="only the rendered scenes, none of the frames of the shipped worlds "
                   "(household.splits)")
    p.add_argument("--config", type=Path, help="YAML overriding config/vqg_data.yaml")
    p.add_argument("--no-progress", action="store_true", help="hide the progress bar")
    p.set_defaults(func=run_data)


def add_train(sub: argparse._SubParsersAction) -> None:
    """Register ``train vqg``."""
    p = sub.add_parser("vqg", help="train the visual question generator",
                       description="Pre-train the image encoder, then the categorical VAE, then "
                       "the adversarial phase with D1 and D2 (thesis §3.4). Writes "
                       "checkpoint.pt (resumable), log_*.csv, valid_log.csv, summary.json "
                       "and the best validated model vqg.pt into --out.")
    p.add_argument("--config", type=Path, help="YAML overriding config/vqg.yaml")
    p.add_argument("--data", type=Path, help="data set folder (default: data.dir)")
    p.add_argument("--out", type=Path, default=Path("runs/vqg-train"), help="run folder")
    p.add_argument("--resume", action="store_true", help="continue the checkpoint in --out "
                   "with the run's own resolved_config.yaml")
    p.add_argument("--export", type=Path, help="also copy vqg.pt here (assets/models/vqg.pt)")
    p.add_argument("--no-progress", action="store_true", help="hide the progress bars")
    p.add_argument("--ablation", choices=["no_d1", "no_d2", "gaussian"],
                   help="train an ablation: without D1, without D2, or a Gaussian latent")
    p.add_argument("--image-from", type=Path, metavar="FILE",
                   help="skip the image phase: reuse another run's image_encoder.pt")
    p.set_defaults(func=run_train)


def add_eval(sub: argparse._SubParsersAction) -> None:
    """Register ``eval vqg``."""
    p = sub.add_parser("vqg", help="distinct questions, DM, RI, RS, BLEU and latency of the "
                       "question generator", description="Sample --samples latent codes for "
                       "each of --images test images and score the distinct questions by "
                       "program (docs/vqg.md). With --ablations, first train the full model "
                       "and each ablation on a shortened schedule and print a table.")
    p.add_argument("--config", type=Path, help="YAML overriding config/vqg.yaml")
    p.add_argument("--data", type=Path, help="data set folder (default: data.dir)")
    p.add_argument("--model", type=Path, default=DEFAULT_MODEL, help="vqg.pt to evaluate")
    p.add_argument("--images", type=integer(1, 100_000),
                   help="test images (default eval.images: 50)")
    p.add_argument("--split", choices=["test", "val"], default="test",
                   help="score these images (val: to tune decode settings, default test)")
    p.add_argument("--samples", type=integer(1, 10_000),
                   help="latent samples per image (default 100)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--out", type=Path, default=Path("runs/vqg-eval"),
                   help="folder for metrics.json")
    p.add_argument("--household", type=Path, nargs="+", metavar="RUNS",
                   help="score the frames household runs saved with their ground truth "
                   "(run folders, or folders holding them: runs/bench-household) instead of "
                   "the data set's split; no BLEU")
    p.add_argument("--ablations", type=Path, metavar="DIR",
                   help="train and evaluate the ablations into DIR (runs/vqg-ablations)")
    p.add_argument("--image-from", type=Path, metavar="FILE",
                   help="with --ablations: reuse this image_encoder.pt in every run")
    p.add_argument("--no-progress", action="store_true", help="hide the progress bars")
    p.set_defaults(func=run_eval)


def add_commands(sub: argparse._SubParsersAction) -> None:
    """Register ``ask``."""
    p = sub.add_parser("ask", help="ask questions about an image (visual question generation)",
                       description="Print up to -n distinct questions about an image (PNG, "
                       "JPEG or another format OpenCV reads, at most 50 MB), best first, one a "
                       "line. Questions the model is unsure of (decode.min_logprob) or that "
                       "the fact check finds unlikely in the image (decode.min_fact_prob) are "
                       "dropped.",
                       epilog="Exit status: 0 when at least one question is printed; 1 when "
                       "every question was dropped (standard error then says how many were "
                       "generated and which check dropped them); 2 for an unreadable image, "
                       "model or config file.")
    p.add_argument("image", type=Path, metavar="IMAGE.png")
    p.add_argument("-n", type=integer(1, 1000), default=10, help="how many questions (default 10)")
    p.add_argument("--model", type=Path, default=DEFAULT_MODEL, help="vqg.pt to use")
    p.add_argument("--seed", type=seed(), default=0, help="seed of the latent codes")
    p.add_argument("--config", type=Path, help="YAML overriding config/vqg.yaml (decode)")
    p.set_defaults(func=run_ask)


def _config(args: argparse.Namespace):
    from perception.vqg.config import load_vqg_config

    cfg = load_vqg_config(args.config)
    if args.data is not None:
        cfg = cfg.model_copy(update={"data": cfg.data.model_copy(
            update={"dir": args.data.resolve()})})
    return cfg


def run_data(args: argparse.Namespace) -> int:
    """Handler of ``companion data vqg``."""
    from perception.vqg.training.data import write_vqg_dataset
    from perception.vqg.training.data_config import load_vqg_data_config

    cfg = load_vqg_data_config(args.config)
    if args.seed is not None:
        cfg = cfg.model_copy(update={"seed": args.seed})
    splits = dict(cfg.splits)
    for name in ("train", "val", "test"):
        value = getattr(args, name)
        if value is not None:
            splits[name] = value
    household = {} if args.no_household else dict(cfg.household.splits)
    write_vqg_dataset(args.out, cfg, splits, progress=not args.no_progress, household=household)
    print(f"VQG data set in {args.out} ({', '.join(f'{k} {v}' for k, v in splits.items())}; "
          f"household frames {', '.join(f'{k} {v}' for k, v in household.items()) or 'none'})")
    return 0


@training_command("vqg")
def run_train(args: argparse.Namespace) -> int:
    """Handler of ``companion train vqg``."""
    from core.run_config import config_for
    from perception.vqg.config import VqgConfig
    from perception.vqg.training.train import train

    cfg = config_for(args, VqgConfig, lambda: _config(args).ablated(args.ablation), "config",
                     "data", "ablation")
    summary = train(cfg, args.out, resume=args.resume, progress=not args.no_progress,
                    image_from=args.image_from)
    if args.export:
        from core.checkpoint import atomic_copy

        atomic_copy(args.out / "vqg.pt", args.export)
    print(json.dumps(summary, indent=2))
    return 0


def run_eval(args: argparse.Namespace) -> int:
    """Handler of ``companion eval vqg``."""
    from perception.vqg.training.ablations import format_table, run_ablations
    from perception.vqg.training.evaluate import evaluate
    from perception.vqg.training.household import evaluate_household

    cfg = _config(args)
    images = args.images or cfg.eval.images
    samples = args.samples or cfg.eval.samples
    if args.ablations is not None:
        ev = cfg.eval.model_copy(update={"images": images, "samples": samples})
        rows = run_ablations(cfg.model_copy(update={"eval": ev}), args.ablations,
                             progress=not args.no_progress, image_from=args.image_from)
        print(json.dumps(rows) if args.json else format_table(rows))
        return 0
    if args.household:
        result = evaluate_household(args.model, cfg, args.household, samples)
    else:
        result = evaluate(args.model, cfg, images, samples, args.split)
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "metrics.json").write_text(json.dumps(result, indent=2))
    if args.json:
        print(json.dumps({k: v for k, v in result.items() if k != "examples"}))
    else:
        bars = cfg.eval.household_bars if args.household else cfg.eval.bars
        for k in ("distinct_per_image", "dm", "ri", "rs", "grounded5_share", "bleu",
                  "latency_ms"):
            if result.get(k) is None:
                continue
            bar = bars.get(k)
            verdict = ("" if bar is None
                       else f"  (bar {bar}: {'pass' if result['pass'][k] else 'FAIL'})")
            print(f"{k:>20}: {result[k]:.3f}{verdict}")
        print(f"{'images':>20}: {result['images']}")
        print(f"\nmetrics.json and examples in {args.out}")
    return 0


def run_ask(args: argparse.Namespace) -> int:
    """Handler of ``companion ask``: the questions on standard output; when none passes the
    checks, why on standard error and exit status 1."""
    from perception.vqg.config import load_vqg_config
    from perception.vqg.generator import VqgQuestionGenerator

    rgb = read_image(args.image)
    decode = load_vqg_config(args.config).decode
    gen = VqgQuestionGenerator.load(args.model, seed=args.seed, decode=decode)
    screening = gen.ask_screened(rgb, args.n)
    for q in screening.questions:
        print(q)
    if screening.questions:
        return 0
    print(f"companion ask: {nothing_passed(screening, decode)}", file=sys.stderr)
    return 1


def nothing_passed(s: Screening, decode: DecodeConfig) -> str:
    """Why no question of ``s`` is left, in one line: how many of those decoded each check
    dropped."""
    confident = s.decoded - s.empty - s.unsure
    dropped = [f"{s.empty} came out empty" if s.empty else "",
               f"{s.unsure} fell below the confidence threshold (mean log-probability per "
               f"word {decode.min_logprob})" if s.unsure else "",
               f"the fact check rejected {confident} ({s.distinct} distinct; plausibility "
               f"below {decode.min_fact_prob})" if confident else ""]
    return (f"no question passed the checks: of {s.decoded} decoded, "
            f"{', '.join(d for d in dropped if d)}; try another --seed or a larger -n")


def read_image(path: Path) -> np.ndarray:
    """The RGB pixels ``(H, W, 3)`` of an image file of at most :data:`IMAGE_LIMIT` bytes,
    read with :func:`core.files.read_bytes`; a file that is no image raises a
    :class:`~core.errors.UserError` naming it."""
    import cv2
    import numpy as np

    data = read_bytes(path, IMAGE_LIMIT)
    try:
        bgr = cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_COLOR)
    except cv2.error:
        bgr = None
    if bgr is None:
        raise UserError(f"{path}: not an image OpenCV can decode (PNG, JPEG, BMP, ...)")
    return np.ascontiguousarray(bgr[..., ::-1])
