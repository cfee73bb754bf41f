"""``companion train style``, ``companion eval style`` and ``companion style``.

Handlers import their heavy modules when called, so that ``companion --help`` stays fast.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from app.core.cli_args import integer
from dialogue.style.config import CLASSIFIER_FILE, DEFAULT_MODEL_DIR, LM_FILE, STYLE_FILE

MODEL_FILES = (STYLE_FILE, CLASSIFIER_FILE, LM_FILE)


def add_train(sub: argparse._SubParsersAction) -> None:
    """Register ``train style``."""
    p = sub.add_parser("style", help="train the mood style-transfer model (Yelp)",
                       description="Train the sentiment classifier, the fluency language model "
                       "and the cross-aligned style-transfer model. Writes checkpoint.pt "
                       "(resumable), log_*.csv, valid_log.csv, summary.json and the model "
                       "files style.pt, classifier.pt and lm.pt into --out.")
    p.add_argument("--config", type=Path, help="style YAML overriding app/defaults/style.yaml")
    p.add_argument("--out", type=Path, default=Path("runs/train-style"), help="run folder")
    p.add_argument("--resume", action="store_true", help="continue the checkpoint in --out")
    p.add_argument("--data", type=Path, help="folder with the Yelp sentiment.* files")
    p.add_argument("--no-style-autoencoder", action="store_true",
                   help="ablation: a plain style embedding instead of the auto-encoder E_y")
    p.add_argument("--export", type=Path,
                   help="also copy the model files into this folder "
                   "(e.g. assets/models/style)")
    p.add_argument("--judges", type=Path,
                   help="reuse the classifier and language model of this earlier run folder "
                   "(same data split) instead of training them, e.g. for the ablation")
    p.add_argument("--no-progress", action="store_true", help="hide the progress bars")
    p.set_defaults(func=run_train)


def add_eval(sub: argparse._SubParsersAction) -> None:
    """Register ``eval style``."""
    p = sub.add_parser("style", help="transfer accuracy, self-BLEU and perplexity of the "
                       "style-transfer model", description="Transfer every held-out sentence "
                       "to the opposite style; report transfer accuracy (TextCNN judge), "
                       "self-BLEU (sacreBLEU), perplexity (LSTM LM), the judge's own accuracy "
                       "and example tables.")
    p.add_argument("--model-dir", type=Path, default=DEFAULT_MODEL_DIR,
                   help="folder with style.pt, classifier.pt and lm.pt")
    p.add_argument("--split", choices=["test", "valid"], default="test")
    p.add_argument("--limit", type=integer(2, 1_000_000),
                   help="evaluate this many sentences (half per style)")
    p.add_argument("--beam", type=integer(1, 64), help="beam size (default: the model's)")
    p.add_argument("--data", type=Path, help="folder with the Yelp sentiment.* files")
    p.add_argument("--threads", type=integer(1, 256), default=1,
                   help="torch CPU threads (default 1)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--out", type=Path, default=Path("runs/eval-style"),
                   help="folder for metrics.json and examples.md")
    p.set_defaults(func=run_eval)


def add_commands(sub: argparse._SubParsersAction) -> None:
    """Register ``style``."""
    p = sub.add_parser("style", help="say sentences in a positive or negative style",
                       description="Translate sentences to the given style, one output line "
                       "per input sentence. Without SENTENCE arguments, sentences are read one "
                       "a line from --input or standard input.")
    p.add_argument("sentences", nargs="*", metavar="SENTENCE")
    p.add_argument("--to", required=True, choices=["positive", "negative"])
    p.add_argument("--input", type=Path, help="file with one sentence a line ('-': stdin)")
    p.add_argument("--model", type=Path, default=DEFAULT_MODEL_DIR / STYLE_FILE,
                   help="style.pt to use")
    p.add_argument("--beam", type=integer(1, 64), help="beam size (default: the model's)")
    p.add_argument("--raw", action="store_true",
                   help="print the model output even when the confidence check rejects it")
    p.set_defaults(func=run_style)


def run_train(args: argparse.Namespace) -> int:
    """Handler of ``companion train style``."""
    from dialogue.style.config import load_style_config
    from dialogue.style.training.train import train

    cfg = load_style_config(args.config)
    if args.data is not None:
        cfg = cfg.model_copy(update={"data": cfg.data.model_copy(
            update={"dir": args.data.resolve()})})
    if args.no_style_autoencoder:
        cfg = cfg.model_copy(update={"model": cfg.model.model_copy(
            update={"style_autoencoder": False})})
    summary = train(cfg, args.out, resume=args.resume, progress=not args.no_progress,
                    judges=args.judges)
    if args.export:
        from app.core.checkpoint import atomic_copy

        args.export.mkdir(parents=True, exist_ok=True)
        for name in MODEL_FILES:
            atomic_copy(args.out / name, args.export / name)
    print(json.dumps(summary, indent=2))
    return 0


def run_eval(args: argparse.Namespace) -> int:
    """Handler of ``companion eval style``."""
    from app.core.torch_threads import torch_threads
    from dialogue.style.training.evaluate import evaluate, examples_markdown, format_summary

    with torch_threads(args.threads):
        result = evaluate(args.model_dir, args.split, args.limit, args.beam,
                          args.data.resolve() if args.data else None)
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "metrics.json").write_text(json.dumps(result, indent=2))
    (args.out / "examples.md").write_text(examples_markdown(result))
    if args.json:
        print(json.dumps({k: v for k, v in result.items() if k != "examples"}))
    else:
        print(format_summary(result))
        print(f"\nmetrics.json and examples.md in {args.out}")
    return 0


def run_style(args: argparse.Namespace) -> int:
    """Handler of ``companion style``: one translation a line on standard output."""
    from dialogue.style.transfer import StyleTransfer

    if args.sentences and args.input is not None:
        raise SystemExit("companion style: give sentences or --input, not both")
    transfer = StyleTransfer.load(args.model, beam_size=args.beam)
    sentences = args.sentences or _read_lines(args.input)
    for start in range(0, len(sentences), 256):
        chunk = sentences[start:start + 256]
        results = transfer.translate_detailed(chunk, args.to)
        for r in results:
            print(r.transferred if args.raw else r.text)
        sys.stdout.flush()
    return 0


def _read_lines(path: Path | None) -> list[str]:
    from app.core.errors import UserError

    if path is None or str(path) == "-":
        text = sys.stdin.read()
    else:
        try:
            text = path.read_text(encoding="utf-8")
        except OSError as exc:
            raise UserError(f"{path}: cannot read ({exc.strerror})") from None
    return [line.strip() for line in text.splitlines()]
