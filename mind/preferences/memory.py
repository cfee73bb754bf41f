"""A household's memory of what its people like, kept between runs in a JSON file.

The file is versioned, written atomically (a temporary file renamed over the old one), and
validated when read: a corrupt or foreign file is refused with one line naming it, never
half-used. Preferences are kept per person, and for the household as a whole (every
feedback, whoever gave it), which the robot uses when it does not know who is there.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated, Literal

import numpy as np
from pydantic import Field, ValidationError

from core.checkpoint import atomic_write_bytes
from core.config_files import StrictModel
from core.errors import UserError
from core.files import FileReadError, read_text
from mind.personality import ACTIONS, Action
from mind.preferences.adaptation import learn

VERSION = 1
HOUSEHOLD = "*household*"   # the row every feedback also teaches
Preference = Annotated[float, Field(ge=-1, le=1)]


class MemoryFileError(UserError):
    """A memory file that cannot be read or is not one."""


class MemoryFile(StrictModel):
    """The file's schema (``version`` first, so a future format is recognised)."""

    version: Literal[1]
    household: str = Field(max_length=200)
    preferences: dict[str, dict[Action, Preference]]
    feedback_events: dict[str, Annotated[int, Field(ge=0)]]


class Memory:
    """Preferences per person (a value in [-1, 1] per action) and how much feedback taught
    them, for one household."""

    def __init__(self, household: str) -> None:
        self.household = household
        self.prefs: dict[str, np.ndarray] = {}
        self.events: dict[str, int] = {}

    def table(self, person: str | None) -> np.ndarray:
        """The preferences to choose with: the person's, or the household's when the person
        is unknown or has given no feedback yet."""
        if person is not None and person in self.prefs:
            return self.prefs[person]
        return self.prefs.get(HOUSEHOLD, np.zeros(len(ACTIONS)))

    def learn(self, person: str | None, action: str, reward: int, rate: float) -> None:
        """Feedback ``reward`` (+1 or -1) for ``action``: it teaches the person's row (when
        known) and the household's."""
        for who in {person or HOUSEHOLD, HOUSEHOLD}:
            row = self.prefs.setdefault(who, np.zeros(len(ACTIONS)))
            learn(row[None], np.zeros(1, int), np.array([ACTIONS.index(action)]),
                  np.array([reward]), rate)    # row[None] is a view: row learns in place
            self.events[who] = self.events.get(who, 0) + 1

    def to_file(self) -> MemoryFile:
        """The file's content."""
        return MemoryFile(version=VERSION, household=self.household,
                          preferences={who: dict(zip(ACTIONS, map(float, row), strict=True))
                                       for who, row in sorted(self.prefs.items())},
                          feedback_events=dict(sorted(self.events.items())))


def load_memory(path: Path, household: str) -> Memory:
    """The memory at ``path``, or an empty one for ``household`` when there is no file."""
    if not path.exists():
        return Memory(household)
    try:
        data = MemoryFile.model_validate(json.loads(read_text(path)))
    except (FileReadError, json.JSONDecodeError, ValidationError) as exc:
        reason = str(exc).splitlines()[0] if not isinstance(exc, ValidationError) else (
            "; ".join(f"{'.'.join(map(str, e['loc']))}: {e['msg']}" for e in exc.errors()[:3]))
        raise MemoryFileError(f"{path}: not a companion memory file ({reason}); move it "
                              "away, or name another file") from None
    memory = Memory(data.household)
    for who, values in data.preferences.items():
        memory.prefs[who] = np.array([values.get(a, 0.0) for a in ACTIONS])
    memory.events = dict(data.feedback_events)
    return memory


def save_memory(memory: Memory, path: Path) -> None:
    """Write ``memory`` to ``path`` atomically."""
    text = json.dumps(memory.to_file().model_dump(mode="json"), indent=2) + "\n"
    atomic_write_bytes(path, text.encode())
