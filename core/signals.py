"""Termination signals as exceptions: inside :func:`terminable`, SIGTERM (what ``timeout``,
``kill`` and container stops send) raises :class:`Terminated`, a ``KeyboardInterrupt``, so a
run or a training stops the way Ctrl-C stops it: everything written so far is kept and the
last files are written. :func:`exit_status` gives the shell's code for the signal (130 for
SIGINT, 143 for SIGTERM)."""

from __future__ import annotations

import contextlib
import signal
import threading
from collections.abc import Iterator
from dataclasses import dataclass
from types import FrameType


class Terminated(KeyboardInterrupt):
    """SIGTERM arrived."""


@dataclass
class Received:
    """Whether SIGTERM arrived within a :func:`terminable` block: code that catches the
    interrupt as a plain ``KeyboardInterrupt`` (as Ray's waits do) can still tell."""

    sigterm: bool = False

    def interrupt(self, caught: KeyboardInterrupt) -> KeyboardInterrupt:
        """``caught``, or a :class:`Terminated` when SIGTERM was what arrived."""
        return Terminated() if self.sigterm and not isinstance(caught, Terminated) else caught


@contextlib.contextmanager
def terminable() -> Iterator[Received]:
    """Within the block, SIGTERM raises :class:`Terminated` (main thread only; elsewhere the
    block runs with the handlers as they are)."""
    received = Received()
    if threading.current_thread() is not threading.main_thread():
        yield received
        return

    def _raise(signum: int, frame: FrameType | None) -> None:
        received.sigterm = True
        raise Terminated()

    previous = signal.signal(signal.SIGTERM, _raise)
    try:
        yield received
    finally:
        signal.signal(signal.SIGTERM, previous)


def exit_status(interrupt: BaseException | None) -> int:
    """0 without an interrupt, 143 for SIGTERM, 130 for SIGINT."""
    return 0 if interrupt is None else status_of(signal_name(interrupt))


def status_of(name: str | None) -> int:
    """The shell's exit status for the signal called ``name`` (0 for None)."""
    return 0 if name is None else 128 + getattr(signal, name)


@contextlib.contextmanager
def shielded() -> Iterator[None]:
    """Within the block, SIGINT and SIGTERM are ignored, so the last files of an interrupted
    run are written whole (the block must be short; main thread only)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {s: signal.signal(s, signal.SIG_IGN) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler)


def signal_name(interrupt: BaseException) -> str:
    """``SIGTERM`` for :class:`Terminated`, else ``SIGINT``."""
    return "SIGTERM" if isinstance(interrupt, Terminated) else "SIGINT"
