"""Stopping a training where its state is whole, and saying so on the command line.

Inside :func:`stop_requests`, SIGINT (Ctrl-C) and SIGTERM do not cut short whatever the
training is doing: they ask it to stop. The training honours the request at its next
:func:`stop_point`, a place between steps where its state (networks, optimizers, data
position, random generators, logs) is consistent: it writes its checkpoint there and raises
``KeyboardInterrupt`` for SIGINT or :class:`~core.signals.Terminated` for SIGTERM, so a
resumed run goes on exactly as an uninterrupted one. A second signal stops it at once and
keeps the last checkpoint; a training that ends before its next stop point ends normally.
A signal the process was started ignoring (SIGINT in a job a script put in the background)
stays ignored.

:func:`training_command` wraps the handler of ``companion train ...``: SIGTERM stops it as
Ctrl-C does, and an interrupted training prints one line saying how to resume it and exits
130 (SIGINT) or 143 (SIGTERM).
"""

from __future__ import annotations

import argparse
import contextlib
import functools
import os
import shlex
import signal
import sys
import threading
from collections.abc import Callable, Iterator
from types import FrameType
from typing import ParamSpec, TypeVar

from core.run_config import CHECKPOINT_FILE
from core.signals import Terminated, exit_status, terminable

P = ParamSpec("P")
R = TypeVar("R")
Handler = Callable[[argparse.Namespace], int]
_requests: list[KeyboardInterrupt] = []  # the stop asked for, if any


def _request(signum: int, frame: FrameType | None) -> None:
    if _requests:  # asked twice: stop now
        raise _requests[0]
    _requests.append(Terminated() if signum == signal.SIGTERM else KeyboardInterrupt())
    name = signal.Signals(signum).name
    os.write(2, f"\ncompanion: stopping at the next checkpoint ({name} again stops at "
                "once)\n".encode())  # not sys.stderr: the handler may run inside its write


@contextlib.contextmanager
def stop_requests() -> Iterator[None]:
    """Within the block, SIGINT and SIGTERM ask for a stop at the next :func:`stop_point`
    (main thread only; elsewhere the block runs with the handlers as they are)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {s: signal.signal(s, _request) for s in (signal.SIGINT, signal.SIGTERM)
                if signal.getsignal(s) is not signal.SIG_IGN}
    try:
        yield
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler)
        _requests.clear()


def stop_point(save: Callable[[], None] | None = None) -> None:
    """Call where the training's state is consistent: when a stop was asked, ``save`` the
    checkpoint (when given) and raise the stop's ``KeyboardInterrupt``."""
    if _requests:
        if save is not None:
            save()
        raise _requests[0]


def stops_first(step: Callable[P, R]) -> Callable[P, R]:
    """``step`` beginning with a :func:`stop_point`, for a loop that checkpoints when its
    step raises ``KeyboardInterrupt`` (:class:`textnets.loop.Run`)."""
    @functools.wraps(step)
    def stepped(*args: P.args, **kwargs: P.kwargs) -> R:
        stop_point()
        return step(*args, **kwargs)
    return stepped


def training_command(what: str) -> Callable[[Handler], Handler]:
    """Decorate the handler of ``companion train <what>`` (see the module docstring)."""
    def decorate(handler: Handler) -> Handler:
        @functools.wraps(handler)
        def run(args: argparse.Namespace) -> int:
            try:
                with terminable():
                    return handler(args)
            except KeyboardInterrupt as exc:
                print(interrupted_line(what, args, exc), file=sys.stderr)
                return exit_status(exc)
        return run
    return decorate


def interrupted_line(what: str, args: argparse.Namespace, exc: KeyboardInterrupt) -> str:
    """The line an interrupted ``companion train <what>`` prints."""
    name = "SIGTERM" if isinstance(exc, Terminated) else "SIGINT"
    kept = ("its checkpoint is kept" if (args.out / CHECKPOINT_FILE).exists()
            else "no checkpoint yet")
    data = f" --data {shlex.quote(str(args.data))}" if getattr(args, "data", None) else ""
    return (f"companion: train {what} interrupted ({name}), {kept}; continue it with: "
            f"companion train {what}{data} --out {shlex.quote(str(args.out))} --resume")
