"""Chat: dialogue turns with the person in front of the robot.

The robot answers what people said to it (the ``heard`` queue, oldest first, lines older
than ``max_heard_age_s`` dropped) through the dialogue manager, with the reply styled by the
current mood; with nothing to answer it opens with ``opener``. The action lasts its Table
4.2 duration (the Relieve leaf); without a person in front it fails at once.
"""

from __future__ import annotations

from typing import Any

import py_trees
from py_trees.common import Status

from behaviours.context import Context
from behaviours.skill import ContextBehaviour, Relieve

HUMAN_PRESENT = 1  # index in the stimuli vector


class SomeoneInFront(ContextBehaviour):
    """SUCCESS while the human-present stimulus is on, else FAILURE (and an event)."""

    def __init__(self, ctx: Context, name: str = "Someone in front?") -> None:
        super().__init__(name, ctx, reads=("stimuli",))

    def update(self) -> Status:
        if self.bb.stimuli[HUMAN_PRESENT] > 0:
            return Status.SUCCESS
        self.emit("no_one_here")
        return Status.FAILURE


class Converse(ContextBehaviour):
    """Answer queued lines one at a time, each after the previous reply has been said."""

    def __init__(self, ctx: Context, name: str = "Converse") -> None:
        super().__init__(name, ctx, reads=("mood",), writes=("heard",))
        self._busy_until = 0.0

    def setup(self, **kwargs: Any) -> None:
        if self.ctx.dialogue is None:
            raise ValueError("the chat skill needs ctx.dialogue (a DialogueManager)")

    def _pending(self) -> list:
        oldest = self.now - self.ctx.config.chat.max_heard_age_s
        return [ev for ev in self.bb.heard if ev.t >= oldest]

    def initialise(self) -> None:
        self._busy_until = self.now
        if not self._pending():
            self._busy_until += self.ctx.speaker.say(self.ctx.config.chat.opener,
                                                     behaviour=self.name)

    def update(self) -> Status:
        pending = self._pending()
        if self.now < self._busy_until or not pending:
            self.bb.heard = pending
            return Status.RUNNING
        said, self.bb.heard = pending[0], pending[1:]
        mood = "positive" if self.bb.mood["positive"] else "negative"
        reply = self.ctx.dialogue.respond(said.text, mood)
        self._busy_until = self.now + self.ctx.speaker.say(
            reply.text, behaviour=self.name, to=said.person, in_reply_to=said.text,
            route=reply.route, mood=mood)
        return Status.RUNNING


def build(ctx: Context) -> py_trees.behaviour.Behaviour:
    """The chat subtree: someone in front? then converse for the action's duration (its
    setup needs ``ctx.dialogue``)."""
    relieve = Relieve("Chat relieves", ctx, "chat")
    talk = py_trees.composites.Parallel(
        "Talk", policy=py_trees.common.ParallelPolicy.SuccessOnSelected(children=[relieve]),
        children=[Converse(ctx), relieve])
    return py_trees.composites.Sequence("Chat", memory=True,
                                        children=[SomeoneInFront(ctx), talk])
