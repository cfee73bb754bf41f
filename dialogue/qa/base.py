"""What every QA handler returns, and the side effect it may ask the robot for."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from core.errors import UserError


@dataclass(frozen=True)
class Action:
    """A side effect for the robot: ``sing_dance`` (with ``song``) or ``take_photo``."""

    name: str
    params: dict[str, Any] = field(default_factory=dict)

    def to_dict(self) -> dict[str, Any]:
        """Plain data for logs and ``--json`` output."""
        return {"name": self.name, **self.params}


@dataclass(frozen=True)
class Answer:
    """A QA answer: what to say, what the tablet shows (URL or file), any action, the topic."""

    text: str
    tablet: str | None = None
    action: Action | None = None
    topic: str | None = None
    found: bool = True  # False when the bot politely could not answer


class DialogueError(UserError):
    """A dialogue data file or option is wrong (a weather block, a feed, a mode)."""
