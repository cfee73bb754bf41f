"""Who the robot says it is: its name and what it likes, from ``persona`` in
``config/conversation.yaml``, answered the same way every time instead of by chit-chat
(which would make up a new name on each asking)."""

from __future__ import annotations

import re

from dialogue.conversation import PersonaConfig, load_conversation_config

ASK_ROBOT_NAME = re.compile(r"\b(?:what(?:'s| is) your name|who are you|what are you called"
                            r"|what (?:should|do|can) i call you|do you have a name)\b", re.I)
ASK_LIKES = re.compile(r"\bwhat (?:else )?(?:do|would) you (?:like|love|enjoy)\b"
                       r"|\bwhat are your (?:hobbies|favou?rite things)\b"
                       r"|\bwhat makes you happy\b", re.I)


def spoken_list(items: list[str]) -> str:
    """``a``, ``a and b``, ``a, b and c``."""
    return ", ".join(items[:-1]) + f" and {items[-1]}" if len(items) > 1 else "".join(items)


class Persona:
    """Answers questions about the robot itself; see :meth:`answer`."""

    def __init__(self, config: PersonaConfig) -> None:
        self.config = config

    @classmethod
    def default(cls) -> Persona:
        """The packaged persona."""
        return cls(load_conversation_config().persona)

    def answer(self, said: str, person: str | None = None) -> str | None:
        """The robot's answer when ``said`` asks its name or what it likes, else None;
        ``person`` is the name the person gave, if any."""
        c = self.config
        if ASK_ROBOT_NAME.search(said):
            you = f" And you're {person}, aren't you?" if person else " What's your name?"
            return f"I'm {c.name}, {c.kind}.{you}"
        if ASK_LIKES.search(said):
            return f"I like {spoken_list(c.likes)}."
        return None
