"""The replies the tablet shows: every reply of the dialogue manager, with its card, kept in
a bounded, thread-safe log that the web server reads and waits on."""

from __future__ import annotations

import threading
from collections import deque
from collections.abc import Callable
from typing import Any

from app.tablet.cards import FileRegistry, card_for
from dialogue.manager import DialogueManager, clean_input


class ReplyLog:
    """The last ``limit`` replies, numbered from 1 (``seq``). Written by whoever runs the
    dialogue (the run loop, or the tablet's dialogue thread), read by the server's threads."""

    def __init__(self, limit: int = 200) -> None:
        self._items: deque[dict[str, Any]] = deque(maxlen=limit)
        self._seq = 0
        self._changed = threading.Condition()

    @property
    def seq(self) -> int:
        """The number of the latest reply (0 before the first)."""
        return self._seq

    def add(self, record: dict[str, Any]) -> dict[str, Any]:
        """Append ``record`` (numbered here) and wake whoever waits for a reply."""
        with self._changed:
            self._seq += 1
            item = {**record, "seq": self._seq}
            self._items.append(item)
            self._changed.notify_all()
        return item

    def after(self, seq: int) -> list[dict[str, Any]]:
        """The replies numbered above ``seq`` still kept."""
        with self._changed:
            return [r for r in self._items if r["seq"] > seq]

    def last(self, n: int) -> list[dict[str, Any]]:
        """The ``n`` latest replies, oldest first."""
        with self._changed:
            return list(self._items)[-n:]

    def wait_for(self, said: str, after: int, timeout: float) -> dict[str, Any] | None:
        """The first reply numbered above ``after`` to the line ``said`` (as the manager
        cleans it), waiting at most ``timeout`` s; None when none came."""
        def found() -> dict[str, Any] | None:
            return next((r for r in self._items if r["seq"] > after and r["input"] == said),
                        None)
        with self._changed:
            self._changed.wait_for(found, timeout)
            return found()


def tap(manager: DialogueManager, log: ReplyLog, files: FileRegistry,
        clock: Callable[[], float], on_record: Callable[[dict[str, Any]], None] | None = None
        ) -> None:
    """Send each reply of ``manager`` (still to its own ``on_reply`` first) into ``log``
    with its card and the time ``clock()``; ``on_record`` then sees the logged record."""
    before = manager.on_reply

    def record(reply: dict[str, Any]) -> None:
        if before is not None:
            before(reply)
        topic = manager.context_of(reply.get("person")).last_topic
        card = card_for(reply, manager.qa, topic, files)
        item = log.add({**reply, "t": round(clock(), 2), "card": card})
        if on_record is not None:
            on_record(item)

    manager.on_reply = record


def said_as(manager: DialogueManager, text: str) -> str:
    """``text`` as ``manager`` will log it (cleaned), to match a reply to its line."""
    return clean_input(text, manager.max_chars)
