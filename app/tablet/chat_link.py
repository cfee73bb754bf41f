"""The tablet alone (``companion tablet``): the dialogue of ``companion chat`` behind the
page, with no household run. The manager (and the photo camera's PyBullet client) lives in
one dialogue thread of its own, so that the server's threads never share it."""

from __future__ import annotations

import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

from app.tablet.cards import FileRegistry
from app.tablet.config import TabletConfig
from app.tablet.live import SnapshotSlot
from app.tablet.replies import ReplyLog, said_as, tap
from dialogue.manager import DialogueManager


class ChatTablet:
    """Lines go straight to the manager; feedback is logged (no action runs to credit)."""

    kind = "chat"

    def __init__(self, manager: DialogueManager, mood: str, mood_value: float,
                 config: TabletConfig, out: Path) -> None:
        self.config, self.manager, self.mood = config, manager, mood
        self.replies = ReplyLog()
        self.files = FileRegistry(out)
        self.slot = SnapshotSlot()
        self._start = time.monotonic()
        self._mood_value = mood_value
        self._feedback: list[dict[str, Any]] = []
        self._thread = ThreadPoolExecutor(1, thread_name_prefix="tablet-dialogue")
        tap(manager, self.replies, self.files, self._elapsed, lambda _: self._publish())
        self._publish()

    @classmethod
    def from_scenario(cls, scenario: Path | None, config: TabletConfig, out: Path
                      ) -> ChatTablet:
        """The dialogue of ``companion chat --scenario`` (its drives give the mood), with
        its maps, photos and reply log in ``out``."""
        from dialogue.cli import DEFAULT_SCENARIO
        from dialogue.factory import chat_session, robot_mood

        manager, drives, personality = chat_session(scenario, DEFAULT_SCENARIO, None, None, out)
        mood, value, _ = robot_mood(drives, personality)
        return cls(manager, mood, value, config, out)

    def _elapsed(self) -> float:
        return time.monotonic() - self._start

    def say(self, text: str, mode: str) -> dict[str, Any]:
        """The manager's reply to ``text`` routed in ``mode`` (in the dialogue thread)."""
        def respond() -> None:
            self.manager.context.mode = mode
            self.manager.respond(text, self.mood)

        after = self.replies.seq
        self._thread.submit(respond)
        reply = self.replies.wait_for(said_as(self.manager, text), after,
                                      self.config.server.reply_timeout_s)
        return reply if reply is not None else {"pending": True}

    def feedback(self, value: int) -> dict[str, Any]:
        """Logged only: outside a run there is no action to credit."""
        self._feedback.append({"t": round(self._elapsed(), 2), "value": value})
        del self._feedback[:-20]
        self._publish()
        return {"queued": False, "value": value, "note": "no running action outside a run"}

    def snapshot(self) -> tuple[int, bytes]:
        """The latest snapshot: the mood and the dialogue."""
        return self.slot.get()

    def _publish(self) -> None:
        self.slot.put({"t": round(self._elapsed(), 2),
                       "mood": {"value": self._mood_value, "positive": self.mood == "positive"},
                       "feedback": self._feedback,
                       "dialogue": self.replies.last(self.config.live.dialogue_lines)})

    def close(self) -> None:
        """Stop the dialogue thread."""
        self._thread.shutdown(wait=False, cancel_futures=True)
