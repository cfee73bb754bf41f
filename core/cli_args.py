"""Argument types for the ``companion`` command: numbers checked for their range while the
command line is parsed, so that a bad value is reported by argparse with the option's name
(``argument --iou: must lie between 0 and 1, got 1.5``) before any work starts. Every number
is finite and bounded: ``nan``, ``inf`` and 23-digit seeds are refused here, not after a run
folder has been made."""

from __future__ import annotations

import argparse
import math
from collections.abc import Callable

from core.limits import SEED_MAX


def integer(minimum: int, maximum: int = 10**9) -> Callable[[str], int]:
    """An integer between ``minimum`` and ``maximum`` (both included)."""

    def parse(text: str) -> int:
        value = int(text)  # argparse reports a ValueError as "invalid integer value"
        if not minimum <= value <= maximum:
            raise argparse.ArgumentTypeError(f"must lie between {minimum} and {maximum}, "
                                             f"got {text if len(text) < 30 else text[:27] + '...'}")
        return value

    parse.__name__ = "integer"
    return parse


def seed() -> Callable[[str], int]:
    """A seed: an integer from 0 to 2^32 - 1."""
    return integer(0, SEED_MAX)


def real(above: float, below: float | None = None) -> Callable[[str], float]:
    """A finite number greater than ``above`` and, when given, smaller than ``below``."""

    def parse(text: str) -> float:
        value = float(text)
        if not math.isfinite(value):
            raise argparse.ArgumentTypeError(f"must be a finite number, got {text}")
        if below is not None and not above < value < below:
            raise argparse.ArgumentTypeError(f"must lie between {above:g} and {below:g}, "
                                             f"got {value:g}")
        if value <= above:
            raise argparse.ArgumentTypeError(f"must be > {above:g}, got {value:g}")
        return value

    parse.__name__ = "number"
    return parse
