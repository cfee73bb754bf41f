"""The ``companion`` command: one entry point with a subcommand per job."""

from __future__ import annotations

import argparse
import sys

from app import __version__
from app.policy import cli as policy_cli


def build_parser() -> argparse.ArgumentParser:
    """The full argument parser (kept import-light so that ``--help`` is fast)."""
    parser = argparse.ArgumentParser(
        prog="companion",
        description="An autonomous social companion robot with moods, in a PyBullet household.")
    parser.add_argument("--version", action="version", version=f"companion {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    train = sub.add_parser("train", help="train a model",
                           description="Train one of the project's models.")
    policy_cli.add_train(train.add_subparsers(dest="model", required=True, metavar="MODEL"))

    evaluate = sub.add_parser("eval", help="evaluate a model against its bars",
                              description="Evaluate one of the project's models.")
    policy_cli.add_eval(evaluate.add_subparsers(dest="model", required=True, metavar="MODEL"))
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the command line; configuration and model-file errors exit with status 2."""
    from app.config import ConfigError
    from app.policy.agent import PolicyFileError

    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except (ConfigError, PolicyFileError, FileExistsError) as exc:
        print(f"companion: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
