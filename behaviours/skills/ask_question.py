"""Ask a question: the robot's curiosity (thesis §3.4). It takes the latest head-camera frame,
samples questions about it from the visual question generator, says the first one it has
not asked before, keeps the frame as a snapshot, and then listens for the action's Table
4.2 duration. Without a question generator the skill fails (no canned questions)."""

from __future__ import annotations

import py_trees
from py_trees.common import Status

from behaviours.context import Context
from behaviours.skill import ContextBehaviour, Relieve


class AskAboutView(ContextBehaviour):
    """Generate and say one question about the current camera frame."""

    def __init__(self, ctx: Context, name: str = "Ask about the view") -> None:
        super().__init__(name, ctx, reads=("frame",))
        self.asked: set[str] = set()
        self._until = 0.0

    def initialise(self) -> None:
        self._until = -1.0
        gen = self.ctx.questions
        if gen is None:
            self.emit("no_question_generator")
            return
        frame = self.bb.frame if self.bb.frame is not None else self.ctx.robot.camera_frame()
        questions = gen.ask(frame, self.ctx.config.ask_question.samples)
        fresh = [q for q in questions if q not in self.asked] or questions
        if not fresh:
            self.emit("no_question")
            return
        question = fresh[0]
        self.asked.add(question)
        snap = self.ctx.snapshot("question", frame) if self.ctx.snapshot else None
        self.emit("question", text=question, frame=snap, candidates=len(set(questions)))
        self._until = self.now + self.ctx.speaker.say(question, behaviour=self.name)

    def update(self) -> Status:
        if self._until < 0:
            return Status.FAILURE
        return Status.SUCCESS if self.now >= self._until else Status.RUNNING


def build(ctx: Context) -> py_trees.behaviour.Behaviour:
    """The ask-question subtree: ask about the view, then listen for the action's duration."""
    return py_trees.composites.Sequence(
        "Ask question", memory=True,
        children=[AskAboutView(ctx), Relieve("Curiosity relieves", ctx, "ask_question")])
