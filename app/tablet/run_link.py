"""The tablet during a household run (``companion run --tablet``).

The run loop is single-threaded and owns PyBullet and the tree; the web server runs in
another thread. The two meet only here: the server puts requests on a bounded, thread-safe
queue (:meth:`RunTablet.say`, :meth:`RunTablet.feedback`); the run drains it once per tick
before its behaviours tick (a pre-tick handler), so that a typed line or a pressed button
enters as a line the robot heard, with its words as typed (touch needs no recognition; onto
the robot's ``tablet`` part for Sense, from in front of the robot, where the tablet is), and
a 👍 / 👎 as a scenario's feedback event (the same part, the same credit rule). Replies
come back through the dialogue manager's reply hook into the
:class:`~app.tablet.replies.ReplyLog` that the server waits on; the live view's snapshots
are built after a tick, at most ``live.snapshot_hz`` times per wall second.
"""

from __future__ import annotations

import queue
from dataclasses import dataclass
from typing import Any

from app.tablet.cards import FileRegistry
from app.tablet.config import TabletConfig
from app.tablet.live import MindView, SnapshotSlot
from app.tablet.replies import ReplyLog, tap
from dialogue.manager import clean_input
from robot.percepts import FeedbackEvent, HeardLine


class BusyError(Exception):
    """The run has too many tablet requests waiting; the server answers 503."""


@dataclass(frozen=True)
class Request:
    """One thing the person did on the tablet: a line (``text``, in ``mode``) or feedback."""

    text: str = ""
    mode: str = "auto"
    value: int = 0


class RunTablet:
    """The tablet's side of a run: requests in, replies and snapshots out."""

    kind = "run"

    def __init__(self, config: TabletConfig) -> None:
        self.config = config
        self.replies = ReplyLog()
        self.slot = SnapshotSlot()
        self.files: FileRegistry | None = None
        self.view: MindView | None = None
        self._requests: queue.Queue[Request] = queue.Queue(config.server.max_queued)
        self.run: Any = None
        self._mode_line: str | None = None   # the tablet line its mode was set for

    def attach(self, run: Any) -> None:
        """Hook into a built :class:`app.run.HouseholdRun` (before its first tick)."""
        self.run = run
        self.files = FileRegistry(run.out)
        if run.ctx.dialogue is not None:
            tap(run.ctx.dialogue, self.replies, self.files, run.ctx.clock, self._replied)
        self.view = MindView(run.ctx, run.tree.root, self.replies, self.slot, self.config.live)
        run.tree.add_pre_tick_handler(self.drain)
        run.tree.add_post_tick_handler(self.view)

    # --- the server's threads -------------------------------------------------------------

    def say(self, text: str, mode: str) -> dict[str, Any]:
        """Say ``text`` to the robot in ``mode``; the reply when it comes within the reply
        timeout, else ``{"pending": True}`` (the page picks it up from the reply log)."""
        after = self.replies.seq
        self._put(Request(text=text, mode=mode))   # before the first tick: heard at it
        said = clean_input(text)
        reply = self.replies.wait_for(said, after, self.config.server.reply_timeout_s)
        return reply if reply is not None else {"pending": True, "input": said}

    def feedback(self, value: int) -> dict[str, Any]:
        """Praise (+1) or scold (-1) the robot for its last action."""
        self._put(Request(value=value))
        return {"queued": True, "value": value}

    def snapshot(self) -> tuple[int, bytes]:
        """The latest live-view snapshot."""
        return self.slot.get()

    def _put(self, request: Request) -> None:
        try:
            self._requests.put_nowait(request)
        except queue.Full:
            raise BusyError from None

    # --- the run loop ---------------------------------------------------------------------

    def drain(self, tree: Any = None) -> None:
        """A pre-tick handler (after the simulation stepped): the waiting requests onto the
        robot's tablet part, as heard lines and feedback events."""
        while True:
            try:
                request = self._requests.get_nowait()
            except queue.Empty:
                return
            if request.value:
                self._feedback(request.value)
            elif self.run.ctx.dialogue is not None:   # a robot without speech hears nothing
                self._hear(request)

    def _hear(self, request: Request) -> None:
        sim, ctx = self.run.sim, self.run.ctx
        person = self.config.person
        yaw = sim.robot.base.pose()[2]          # typed at the chest tablet: the words as given
        line = HeardLine(sim.line_number(), sim.t, person, request.text, "robot", yaw)
        ctx.dialogue.context_of(person).mode = request.mode
        self._mode_line = clean_input(request.text) if request.mode != "auto" else None
        ctx.events.emit("tablet_line", line=line.line, text=request.text, mode=request.mode)
        ctx.robot.tablet.touch(line)

    def _feedback(self, value: int) -> None:
        sim, ctx = self.run.sim, self.run.ctx
        ctx.events.emit("tablet_feedback", value=value)
        ctx.robot.tablet.touch(FeedbackEvent(sim.t, self.config.person, value, None))

    def _replied(self, record: dict[str, Any]) -> None:
        """Once the tablet line chosen in a mode is answered, the robot routes by itself
        again (the button chose the kind of that one conversation turn)."""
        if self._mode_line is not None and record["input"] == self._mode_line:
            self.run.ctx.dialogue.context_of(self.config.person).mode = "auto"
            self._mode_line = None
