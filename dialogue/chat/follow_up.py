"""Follow-up lines: what "she", "he" or "it" most likely refer to in a chit-chat line.

The seq2seq answers one line at a time, so "She hasn't called me this week." after "My
daughter moved to Leeds." would be answered as if "she" could be anyone. Three small rules,
with the word lists of ``follow_up`` in ``config/chat.yaml``:

* **People**: "she"/"her" ("he"/"him") in a line that names nobody itself becomes the most
  recent "my <relative>" of the matching list in the person's last ``turns`` lines
  ("My daughter hasn't called me this week.").
* **No echo**: the robot's replies of those turns are not said again straight away.
* **Topics**: a short line (at most ``max_words`` words) with "it", "that", "this" or "there"
  borrows the words of the person's previous line, and the dialogue's last QA topic, for the
  ranking's topic term only ("Why is that?" after "I love gardening." favours a reply about
  gardening, but retrieval still looks for lines like "Why is that?": searching with the
  borrowed words too found the earlier line's answers again).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from itertools import pairwise

from dialogue.chat.config import ChatFollowUpConfig
from dialogue.chat.text import tokenize

GENDER = {"she": "female", "her": "female", "he": "male", "him": "male"}
TOPIC_WORDS = {"it", "that", "this", "there"}
PRONOUN = re.compile(r"\b(she|her|he|him)\b", re.I)


@dataclass(frozen=True)
class FollowUp:
    """The line to answer (people named again), the text a reply's topic is compared with,
    and the robot's recent replies (not to be said again straight away)."""

    line: str
    topic: str
    robot_said: frozenset[str] = frozenset()


def recent_turns(context: object, turns: int) -> list[tuple[str, str]]:
    """The last ``turns`` ``(person's line, robot's reply)`` pairs of ``context.history``,
    most recent first (any other context gives none)."""
    history = list(getattr(context, "history", None) or ())
    return list(reversed(history[-turns:])) if turns else []


def mentioned(lines: list[str], words: list[str]) -> str | None:
    """The first "my <word>" of ``lines`` (most recent first) with a word from ``words``."""
    for line in lines:
        tokens = tokenize(line)
        for a, b in pairwise(tokens):
            if a == "my" and b in words:
                return b
    return None


def resolve(line: str, context: object, cfg: ChatFollowUpConfig) -> FollowUp:
    """``line`` with its pronouns resolved, and its topic text (see the module doc)."""
    recent = recent_turns(context, cfg.turns)
    earlier = [said for said, _ in recent]
    tokens = tokenize(line)
    relatives = {"female": cfg.female, "male": cfg.male}
    if not set(tokens) & {*cfg.female, *cfg.male}:
        who = {g: mentioned(earlier, words) for g, words in relatives.items()}

        def name_again(m: re.Match[str]) -> str:
            person = who[GENDER[m.group(1).lower()]]
            if person is None:
                return m.group(0)
            return f"My {person}" if m.start() == 0 and m.group(1)[0].isupper() \
                else f"my {person}"

        line = PRONOUN.sub(name_again, line)
    words = [t for t in tokens if t[:1].isalnum()]
    topic = line
    if set(tokens) & TOPIC_WORDS and len(words) <= cfg.max_words:
        last = getattr(context, "last_topic", None)
        topic = " ".join([line, *earlier[:1], *([str(last)] if last else [])])
    return FollowUp(line, topic, frozenset(reply for _, reply in recent))
