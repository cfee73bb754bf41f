"""The run's event log: one JSON object a line, flushed as it is written."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path
from typing import IO, Any

import numpy as np


def _plain(value: Any) -> Any:
    if isinstance(value, np.ndarray):
        return [round(float(v), 5) for v in value]
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, float):
        return round(value, 5)
    return value


class EventLog:
    """Appends ``{"t": ..., "kind": ..., ...}`` lines to ``path`` (or only keeps them in
    memory when ``path`` is None). ``clock`` gives the simulated time of each event."""

    def __init__(self, path: str | Path | None, clock: Callable[[], float]) -> None:
        self.clock = clock
        self.events: list[dict[str, Any]] = []
        self._fh: IO[str] | None = None
        if path is not None:
            Path(path).parent.mkdir(parents=True, exist_ok=True)
            self._fh = open(path, "w", encoding="utf-8")  # noqa: SIM115 - closed in close()

    def emit(self, kind: str, **fields: Any) -> dict[str, Any]:
        """Record one event now; returns it."""
        event = {"t": round(self.clock(), 3), "kind": kind,
                 **{k: _plain(v) for k, v in fields.items()}}
        self.events.append(event)
        if self._fh is not None:
            self._fh.write(json.dumps(event, ensure_ascii=False) + "\n")
            self._fh.flush()
        return event

    def of_kind(self, kind: str) -> list[dict[str, Any]]:
        """Every event of one kind, in order."""
        return [e for e in self.events if e["kind"] == kind]

    def close(self) -> None:
        """Close the file (the events stay in memory)."""
        if self._fh is not None:
            self._fh.close()
            self._fh = None
