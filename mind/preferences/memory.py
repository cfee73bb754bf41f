"""A household's memory of what its people like and tell it, kept between runs in a JSON
file.

The file is versioned, written atomically (a temporary file renamed over the old one), and
validated when read: a corrupt or foreign file is refused with one line naming it, never
half-used; a version 1 file (preferences only) is read as one with nothing told yet.
Preferences are kept per person, and for the household as a whole (every feedback, whoever
gave it), which the robot uses when it does not know who is there. What people tell about
themselves (a visit coming, a sore knee, a worry, their old job) is kept per person as
:class:`Fact` s, at most :data:`MAX_FACTS` each, the oldest forgotten first.
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

VERSION = 2
HOUSEHOLD = "*household*"   # the row every feedback also teaches
MAX_FACTS = 20              # kept per person
FACT_KINDS = ("name", "visit", "ailment", "worry", "job", "pet", "family", "like")
Preference = Annotated[float, Field(ge=-1, le=1)]


class MemoryFileError(UserError):
    """A memory file that cannot be read or is not one."""


class Fact(StrictModel):
    """Something a person told the robot about themselves: its kind, how the robot says it
    back ("your daughter Susan"), when it is ("on Sunday", "" for none), and whether the
    robot has asked about it since."""

    kind: Literal[FACT_KINDS]  # type: ignore[valid-type]
    said: str = Field(min_length=1, max_length=200)
    when: str = Field(default="", max_length=40)
    asked: bool = False


class MemoryFile(StrictModel):
    """The file's schema (``version`` first, so a future format is recognised)."""

    version: Literal[1, 2]
    household: str = Field(max_length=200)
    preferences: dict[str, dict[Action, Preference]]
    feedback_events: dict[str, Annotated[int, Field(ge=0)]]
    facts: dict[str, list[Fact]] = Field(default_factory=dict)


class Memory:
    """Preferences per person (a value in [-1, 1] per action) and how much feedback taught
    them, for one household."""

    def __init__(self, household: str) -> None:
        self.household = household
        self.prefs: dict[str, np.ndarray] = {}
        self.events: dict[str, int] = {}
        self.facts: dict[str, list[Fact]] = {}

    def remember(self, person: str, fact: Fact) -> bool:
        """Keep ``fact`` about ``person`` (replacing one of the same kind about the same
        thing); False when it was known already."""
        kept = self.facts.setdefault(person, [])
        same = [f for f in kept if f.kind == fact.kind and f.said == fact.said]
        if same and same[0].when == fact.when:
            return False
        self.facts[person] = [*[f for f in kept if f not in same][-(MAX_FACTS - 1):], fact]
        return True

    def forget_last(self, person: str) -> Fact | None:
        """Forget the last thing ``person`` told (the fact, None when there was none)."""
        kept = self.facts.get(person) or []
        if not kept:
            return None
        self.facts[person] = kept[:-1]
        return kept[-1]

    def to_ask(self, person: str, kinds: tuple[str, ...]) -> Fact | None:
        """The latest fact about ``person`` of one of ``kinds`` not asked about yet; it is
        marked asked."""
        kept = self.facts.get(person) or []
        for i in range(len(kept) - 1, -1, -1):
            if kept[i].kind in kinds and not kept[i].asked:
                kept[i] = kept[i].model_copy(update={"asked": True})
                return kept[i]
        return None

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
                          feedback_events=dict(sorted(self.events.items())),
                          facts=dict(sorted(self.facts.items())))


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
    memory.facts = {who: list(facts) for who, facts in data.facts.items()}
    return memory


def save_memory(memory: Memory, path: Path) -> None:
    """Write ``memory`` to ``path`` atomically."""
    text = json.dumps(memory.to_file().model_dump(mode="json"), indent=2) + "\n"
    atomic_write_bytes(path, text.encode())
