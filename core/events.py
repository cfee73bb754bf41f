"""The run's event log: one JSON object a line, each written whole in one system call, so a
run killed at any moment (even by SIGKILL) leaves only complete lines behind."""

from __future__ import annotations

import json
import os
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np


def _plain(value: Any) -> Any:
    if isinstance(value, np.ndarray):
        return [round(float(v), 5) for v in value]
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, float):
        return round(value, 5)
    return value


class LineFile:
    """A file written from its start in whole pieces: each :meth:`write` is one ``write``
    system call (repeated only for what the kernel did not take, never a buffered part), and
    a piece that fails half-way (a full disk) is cut off again before the error goes up."""

    def __init__(self, path: str | Path) -> None:
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._fd: int | None = os.open(self.path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC,
                                       0o644)
        self._size = 0

    def write(self, text: str) -> None:
        """Append ``text`` whole or not at all (closed files ignore it)."""
        if self._fd is None:
            return
        raw = text.encode("utf-8")
        data = memoryview(raw)
        try:
            while data:
                data = data[os.write(self._fd, data):]
        except OSError:
            os.ftruncate(self._fd, self._size)
            os.lseek(self._fd, self._size, os.SEEK_SET)
            raise
        self._size += len(raw)

    def close(self) -> None:
        """Close the file."""
        if self._fd is not None:
            os.close(self._fd)
            self._fd = None


class EventLog:
    """Appends ``{"t": ..., "kind": ..., ...}`` lines to ``path`` (or only keeps them in
    memory when ``path`` is None). ``clock`` gives the simulated time of each event."""

    def __init__(self, path: str | Path | None, clock: Callable[[], float]) -> None:
        self.clock = clock
        self.events: list[dict[str, Any]] = []
        self._file = LineFile(path) if path is not None else None

    def emit(self, kind: str, **fields: Any) -> dict[str, Any]:
        """Record one event now; returns it."""
        event = {"t": round(self.clock(), 3), "kind": kind,
                 **{k: _plain(v) for k, v in fields.items()}}
        self.events.append(event)
        if self._file is not None:
            self._file.write(json.dumps(event, ensure_ascii=False) + "\n")
        return event

    def of_kind(self, kind: str) -> list[dict[str, Any]]:
        """Every event of one kind, in order."""
        return [e for e in self.events if e["kind"] == kind]

    def close(self) -> None:
        """Close the file (the events stay in memory)."""
        if self._file is not None:
            self._file.close()
