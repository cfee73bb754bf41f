"""Argument types for the ``companion`` command: numbers checked for their range while the
command line is parsed, so that a bad value is reported by argparse with the option's name
(``argument --iou: must lie between 0 and 1, got 1.5``) before any work starts."""

from __future__ import annotations

import argparse
from collections.abc import Callable


def integer(minimum: int) -> Callable[[str], int]:
    """An integer no smaller than ``minimum``."""

    def parse(text: str) -> int:
        value = int(text)  # argparse reports a ValueError as "invalid integer value"
        if value < minimum:
            raise argparse.ArgumentTypeError(f"must be >= {minimum}, got {value}")
        return value

    parse.__name__ = "integer"
    return parse


def real(above: float, below: float | None = None) -> Callable[[str], float]:
    """A number greater than ``above`` and, when given, smaller than ``below``."""

    def parse(text: str) -> float:
        value = float(text)
        if below is not None and not above < value < below:
            raise argparse.ArgumentTypeError(f"must lie between {above:g} and {below:g}, "
                                             f"got {value:g}")
        if value <= above:
            raise argparse.ArgumentTypeError(f"must be > {above:g}, got {value:g}")
        return value

    parse.__name__ = "number"
    return parse
