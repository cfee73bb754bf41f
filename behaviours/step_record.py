"""The homeostasis steps of a run, kept in bounded memory.

Each step (one simulated second by default) gives a row: action, drives, motivations,
stimuli, mood, and whether the drives are secure. A run of any length keeps only running
totals for the report, the last row, and the rows its timeline writer has not taken yet;
the whole series lives in ``timeline.csv``.
"""

from __future__ import annotations

from collections import Counter
from typing import Any

import numpy as np


class StepRecord:
    """Running totals of a run's homeostasis steps (RSR, time per action, mood share, the
    highest drives), the last row, and the rows not yet taken by :meth:`take`."""

    def __init__(self) -> None:
        self.steps = 0
        self.secure_steps = 0
        self.mood_positive_steps = 0
        self.action_steps: Counter[str] = Counter()
        self.max_drives: np.ndarray | None = None
        self.last: dict[str, Any] | None = None
        self._pending: list[dict[str, Any]] = []

    def append(self, row: dict[str, Any]) -> None:
        """Count one step's row (keys ``action``, ``drives``, ``mood_positive``, ``secure``,
        and whatever the timeline writes) and keep it until taken."""
        self.steps += 1
        self.secure_steps += bool(row["secure"])
        self.mood_positive_steps += bool(row["mood_positive"])
        self.action_steps[row["action"]] += 1
        drives = np.asarray(row["drives"], float)
        self.max_drives = drives.copy() if self.max_drives is None else np.maximum(
            self.max_drives, drives)
        self.last = row
        self._pending.append(row)

    def take(self) -> list[dict[str, Any]]:
        """The rows appended since the last call (the caller writes them out)."""
        rows, self._pending = self._pending, []
        return rows

    @property
    def last_action(self) -> str | None:
        """The action of the latest step, or None before the first."""
        return None if self.last is None else self.last["action"]
