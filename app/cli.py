"""The ``companion`` command: one entry point with a subcommand per job.

Each domain keeps its own command-line module exposing any of ``add_train``, ``add_eval``,
``add_data``, ``add_export``, ``add_bench`` (each receives the subparsers of that group) and
``add_commands`` (receives the top-level subparsers); :data:`DOMAINS` lists those modules.
"""

from __future__ import annotations

import argparse
import importlib
import sys

from app import __version__
from core.errors import UserError
from core.signals import exit_status, signal_name, terminable

DOMAINS = ["mind.policy.training.cli", "mind.preferences.evaluation.cli",
           "mind.preferences.cli",
           "dialogue.cli", "dialogue.style.training.cli", "dialogue.style.training.mood_cli",
           "dialogue.chat.training.cli", "dialogue.acts.training.cli",
           "dialogue.speech.training.cli",
           "perception.detector.training.cli",
           "perception.vqg.training.cli", "perception.facing.training.cli", "app.run_cli",
           "app.sweep.cli", "app.tablet.cli"]
GROUPS = {"train": "train a model", "eval": "evaluate a model against its bars",
          "data": "generate a data set", "export": "export a trained model for the robot",
          "bench": "measure the whole robot"}


def build_parser() -> argparse.ArgumentParser:
    """The full argument parser (kept import-light so that ``--help`` is fast)."""
    parser = argparse.ArgumentParser(
        prog="companion",
        description="An autonomous social companion robot with moods, in a PyBullet household.")
    parser.add_argument("--version", action="version", version=f"companion {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    modules = [importlib.import_module(name) for name in DOMAINS]
    for group, help_text in GROUPS.items():
        hooks = [getattr(m, f"add_{group}") for m in modules if hasattr(m, f"add_{group}")]
        if not hooks:
            continue
        group_parser = sub.add_parser(group, help=help_text, description=help_text.capitalize())
        group_sub = group_parser.add_subparsers(dest="target", required=True, metavar="WHAT")
        for hook in hooks:
            hook(group_sub)
    for m in modules:
        if hasattr(m, "add_commands"):
            m.add_commands(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the command line: configuration, input and model-file errors exit with status 2,
    and SIGINT or SIGTERM before a command's own handling exits 130 or 143."""
    args = build_parser().parse_args(argv)
    try:
        with terminable():
            return args.func(args)
    except (UserError, FileExistsError) as exc:
        print(f"companion: error: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:   # the file system refused (full disk, permissions, a lost mount)
        where = f"{exc.filename}: " if exc.filename else ""
        print(f"companion: error: {where}{exc.strerror or exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt as exc:
        print(f"companion: interrupted ({signal_name(exc)})", file=sys.stderr)
        return exit_status(exc)


if __name__ == "__main__":
    sys.exit(main())
