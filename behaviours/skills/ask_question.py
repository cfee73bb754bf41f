"""Ask a question: the robot's curiosity (thesis §3.4). It takes the latest head-camera frame,
samples questions about it from the visual question generator, keeps those its own senses
do not contradict (the question grammar reads them; a question about a person needs a
person box from the detector), says the first one it has not asked before, keeps the frame
as a snapshot, and then listens for the action's Table 4.2 duration. With no question left
but a person in view, it says where it sees them instead (a ``remark``); with neither the
skill fails. Without a question generator the skill fails (no canned questions)."""

from __future__ import annotations

import py_trees
from py_trees.common import Status

from behaviours.context import Context
from behaviours.skill import ContextBehaviour, Relieve, people_in_view
from perception.detector.yolo import Detection
from perception.vqg.questions import about_people, parse_question


class AskAboutView(ContextBehaviour):
    """Generate and say one question about the current camera frame (or a remark)."""

    def __init__(self, ctx: Context, name: str = "Ask about the view") -> None:
        super().__init__(name, ctx, reads=("frame", "detections"))
        self.asked: set[str] = set()
        self._until = 0.0

    def _checked(self, questions: list[str], people: list[Detection]) -> list[str]:
        """The questions the robot's own senses do not contradict."""
        frames = [parse_question(q) for q in questions]
        return [q for q, f in zip(questions, frames, strict=True)
                if f is not None and (people or not about_people(f))]

    def _remark(self, people: list[Detection], width: int) -> str | None:
        """Where the robot sees someone (the largest person box), or None."""
        if not people:
            return None
        x = people[0].centre[0] / width
        where = "on my left" if x < 1 / 3 else "on my right" if x > 2 / 3 else "in front of me"
        return f"I can see someone {where}." if len(people) == 1 else \
            f"I can see {len(people)} people here, one {where}."

    def initialise(self) -> None:
        self._until = -1.0
        gen = self.ctx.questions
        if gen is None:
            self.emit("no_question_generator")
            return
        frame = self.bb.frame if self.bb.frame is not None else self.ctx.robot.camera.frame()
        people = people_in_view(self.ctx, self.bb.detections)
        questions = gen.ask(frame, self.ctx.config.ask_question.samples)
        checked = self._checked(questions, people)
        fresh = [q for q in checked if q not in self.asked] or checked
        snap = self.ctx.snapshot("question", frame) if self.ctx.snapshot else None
        if fresh:
            text = fresh[0]
            self.asked.add(text)
            self.emit("question", text=text, frame=snap, candidates=len(set(questions)),
                      kept=len(checked))
        else:
            text = self._remark(people, frame.shape[1])
            self.emit("remark" if text else "no_question", text=text, frame=snap,
                      candidates=len(set(questions)))
            if text is None:
                return
        self._until = self.now + self.ctx.speaker.say(text, behaviour=self.name)

    def update(self) -> Status:
        if self._until < 0:
            return Status.FAILURE
        return Status.SUCCESS if self.now >= self._until else Status.RUNNING


def build(ctx: Context) -> py_trees.behaviour.Behaviour:
    """The ask-question subtree: ask about the view, then listen for the action's duration."""
    return py_trees.composites.Sequence(
        "Ask question", memory=True,
        children=[AskAboutView(ctx), Relieve("Curiosity relieves", ctx, "ask_question")])
