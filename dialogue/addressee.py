"""Who a heard line is said to, from its words: the robot answers a line unless the speaker
calls someone else by name (docs/speech.md, *Who a line is for*).

People address each other with a vocative: "Margaret, shall we do the crossword?", "Cheer
up, Harold.", "Dad, would you like some cake?". The recogniser's transcripts have neither
capitals nor commas, so a vocative is looked for where it most often stands in speech: the
first word of the line once openers ("hello", "oh", "cheer up") are skipped. A
vocative that is the robot's name or "robot" makes the line the robot's; "everyone" makes
it everyone's, the robot included; a household member's name or a family title ("dad",
"grandma") makes it someone else's. A line that names nobody is taken as said to the robot,
as most lines near a companion robot are. Words alone cannot tell a line like "Just a small
slice, thank you." said to a neighbour at the table, nor a vocative at the end ("Some cake,
Dad?"), which without commas looks like any name that ends a line ("Have you seen
Harold?"): such lines are answered.
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from dataclasses import dataclass

from dialogue.conversation import AddresseeConfig, load_conversation_config
from robot.percepts import AUDIENCES

ROBOT, EVERYONE = AUDIENCES
_WORD = re.compile(r"[a-z]+(?:'[a-z]+)?")


@dataclass(frozen=True)
class Addressee:
    """``to``: ``robot``, ``everyone`` or the word that named someone else; ``cue``: the
    vocative that decided it (empty: nobody was named, so the robot)."""

    to: str
    cue: str = ""

    @property
    def to_robot(self) -> bool:
        """Whether the robot should take the line as said to it."""
        return self.to in AUDIENCES


class AddresseeJudge:
    """Finds the vocative of a line; ``household`` are the names of the people the robot
    lives with (set up by its owner, like the map of the home)."""

    def __init__(self, robot_name: str, household: Iterable[str],
                 config: AddresseeConfig | None = None) -> None:
        cfg = config or load_conversation_config().addressee
        self.robot = {robot_name.lower(), *cfg.robot_words}
        self.everyone = set(cfg.group_words)
        self.others = ({w for name in household for w in _WORD.findall(name.lower())}
                       | set(cfg.family_words)) - self.robot
        self.openers = [o.split() for o in sorted(cfg.openers, key=lambda o: -len(o.split()))]
        self.first_words = cfg.first_words

    def judge(self, text: str) -> Addressee:
        """Who ``text`` (a transcript, or typed words) is said to."""
        words = _WORD.findall(text.lower())
        start = self._after_openers(words)
        for word in words[start:start + self.first_words]:
            if word in self.robot:
                return Addressee(ROBOT, word)
            if word in self.everyone:
                return Addressee(EVERYONE, word)
            if word in self.others:
                return Addressee(word, word)
        return Addressee(ROBOT)

    def names_robot(self, text: str) -> bool:
        """Whether ``text`` calls the robot anywhere ("Well done, robot"), not only first."""
        return not self.robot.isdisjoint(_WORD.findall(text.lower()))

    def _after_openers(self, words: list[str]) -> int:
        """Where the line starts once greetings and fillers are skipped."""
        at, moved = 0, True
        while moved:
            moved = False
            for opener in self.openers:
                if words[at:at + len(opener)] == opener:
                    at, moved = at + len(opener), True
                    break
        return at
