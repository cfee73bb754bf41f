"""``companion train style``, ``companion eval style`` and ``companion style``.

Handlers import their heavy modules when called, so that ``companion --help`` stays fast.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from core.cli_args import integer
from core.interrupts import training_command
from dialogue.style.config import (
    CLASSIFIER_FILE,
    DEFAULT_MODEL_DIR,
    LM_FILE,
    STYLE_FILE,
    StyleConfig,
)

if TYPE_CHECKING:
    from dialogue.style.transfer import Translation

MODEL_FILES = (STYLE_FILE, CLASSIFIER_FILE, LM_FILE)


def add_train(sub: argparse._SubParsersAction) -> None:
    """Register ``train style``."""
    p = sub.add_parser("style", help="train the mood style-transfer model (Yelp)",
                       description="Train the sentiment classifier, the fluency language model "
                       "and the cross-aligned style-transfer model. Writes checkpoint.pt "
                       "(resumable), log_*.csv, valid_log.csv, summary.json and the model "
                       "files style.pt, classifier.pt and lm.pt into --out.")
    p.add_argument("--config", type=Path, help="style YAML overriding config/style.yaml")
    p.add_argument("--out", type=Path, default=Path("runs/train-style"), help="run folder")
    p.add_argument("--resume", action="store_true", help="continue the checkpoint in --out "
                   "with the run's own resolved_config.yaml")
    p.add_argument("--data", type=Path, help="folder with the Yelp sentiment.* files")
    p.add_argument("--no-style-autoencoder", action="store_true",
                   help="ablation: a plain style embedding instead of the auto-encoder E_y")
    p.add_argument("--export", type=Path,
                   help="also copy the model files into this folder "
                   "(e.g. assets/models/style)")
    p.add_argument("--judges", type=Path,
                   help="reuse the classifier and language model of this earlier run folder "
                   "(same data split) instead of training them, e.g. for the ablation")
    p.add_argument("--init", type=Path,
                   help="start the transfer model from this style.pt (same vocabulary and "
                   "sizes) instead of from scratch: fine-tuning, e.g. on conversation")
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
                       "per input line (each SENTENCE argument is a line). Without SENTENCE "
                       "arguments, lines are read from --input or standard input (UTF-8, at "
                       "most 1 MB). A line with several sentences is translated sentence by "
                       "sentence. A sentence the model cannot translate faithfully (longer "
                       "than its word limit, too few words it knows, as in text that is not "
                       "English, or a translation that loses the content) is printed "
                       "unchanged, and standard error says why.",
                       epilog="Exit status: 0 when every sentence was translated; 1 when some "
                       "were printed unchanged; 2 when nothing could be done (empty input, an "
                       "unreadable --input file or model file).")
    p.add_argument("sentences", nargs="*", metavar="SENTENCE")
    p.add_argument("--to", required=True, choices=["positive", "negative"])
    p.add_argument("--input", type=Path, help="file with one sentence a line ('-': stdin)")
    p.add_argument("--model", type=Path, default=DEFAULT_MODEL_DIR / STYLE_FILE,
                   help="style.pt to use")
    p.add_argument("--beam", type=integer(1, 64), help="beam size (default: the model's)")
    p.add_argument("--raw", action="store_true",
                   help="print the model output even when the confidence check rejects it")
    p.set_defaults(func=run_style)


@training_command("style")
def run_train(args: argparse.Namespace) -> int:
    """Handler of ``companion train style``."""
    from core.run_config import config_for
    from dialogue.style.training.train import train

    cfg = config_for(args, StyleConfig, lambda: _train_config(args), "config", "data",
                     "no_style_autoencoder")
    summary = train(cfg, args.out, resume=args.resume, progress=not args.no_progress,
                    judges=args.judges, init=args.init)
    if args.export:
        from core.checkpoint import atomic_copy

        args.export.mkdir(parents=True, exist_ok=True)
        for name in MODEL_FILES:
            atomic_copy(args.out / name, args.export / name)
    print(json.dumps(summary, indent=2))
    return 0


def _train_config(args: argparse.Namespace) -> StyleConfig:
    """The style config that ``--config``, ``--data`` and ``--no-style-autoencoder`` give."""
    from dialogue.style.config import load_style_config

    cfg = load_style_config(args.config)
    if args.data is not None:
        cfg = cfg.model_copy(update={"data": cfg.data.model_copy(
            update={"dir": args.data.resolve()})})
    if args.no_style_autoencoder:
        cfg = cfg.model_copy(update={"model": cfg.model.model_copy(
            update={"style_autoencoder": False})})
    return cfg


def run_eval(args: argparse.Namespace) -> int:
    """Handler of ``companion eval style``."""
    from core.torch_threads import torch_threads
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
    """Handler of ``companion style``: one output line per input line on standard output, a
    notice on standard error for each sentence printed unchanged (exit status 1)."""
    from core.errors import UserError
    from dialogue.style.text import split_sentences
    from dialogue.style.transfer import StyleTransfer

    if args.sentences and args.input is not None:
        raise UserError("give sentences or --input, not both")
    lines = [split_sentences(line) for line in args.sentences or _read_lines(args.input)]
    if not any(lines):
        raise UserError("nothing to transfer: the input is empty")
    transfer = StyleTransfer.load(args.model, beam_size=args.beam)
    report = Report(args.raw)
    for start in range(0, len(lines), 256):
        chunk = lines[start:start + 256]
        results = iter(transfer.translate_detailed([s for line in chunk for s in line], args.to))
        for number, line in enumerate(chunk, start + 1):
            wheres = [f"line {number}, sentence {i}" for i in range(1, len(line) + 1)]
            wheres = wheres if len(line) > 1 else [f"line {number}"] * len(line)
            print(" ".join(report.said(next(results), where) for where in wheres))
        sys.stdout.flush()
    return report.close()


class Report:
    """What to print for each sentence (with ``raw``, the model's output even when the
    confidence check rejects it), and on standard error why a sentence is printed unchanged:
    the first :attr:`SHOWN` one a line, then how many in all."""

    SHOWN = 20

    def __init__(self, raw: bool) -> None:
        self.raw, self.total, self.unchanged = raw, 0, 0

    def said(self, result: Translation, where: str) -> str:
        """The text to print for one sentence; ``where`` names it in a notice."""
        self.total += 1
        if self.raw and result.transferred:
            return result.transferred
        if result.reason is not None:
            self.unchanged += 1
            if self.unchanged <= self.SHOWN:
                print(f"companion style: {where}: printed unchanged: {result.reason}",
                      file=sys.stderr, flush=True)
        return result.text

    def close(self) -> int:
        """Sum up; the exit status: 1 when a sentence was printed unchanged, else 0."""
        if self.unchanged:
            print(f"companion style: {self.unchanged} of {self.total} sentences printed "
                  "unchanged", file=sys.stderr)
        return 1 if self.unchanged else 0


def _read_lines(path: Path | None) -> list[str]:
    """The lines of the file ``path`` (see :func:`core.files.read_text`), or of standard
    input without one or for '-'."""
    from core.errors import UserError
    from core.files import TEXT_LIMIT, read_text

    if path is not None and str(path) != "-":
        return read_text(path).splitlines()
    if sys.stdin.isatty():
        print("companion style: reading lines from standard input; end with Ctrl-D",
              file=sys.stderr)
    try:
        text = sys.stdin.read(TEXT_LIMIT + 1)
        text.encode("utf-8")  # standard input may keep undecodable bytes as surrogates
    except (UnicodeDecodeError, UnicodeEncodeError):
        raise UserError("standard input: not UTF-8 text") from None
    if "\x00" in text:
        raise UserError("standard input: binary data (or UTF-16 text), expected UTF-8 text")
    if len(text) > TEXT_LIMIT:
        raise UserError(f"standard input: more than the {TEXT_LIMIT:,}-character limit; "
                        "split it into smaller parts")
    return text.splitlines()
