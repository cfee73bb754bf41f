"""The ask-question skill says only questions its own senses do not contradict, and a remark
about who it sees when no question is left."""

from __future__ import annotations

import numpy as np
import py_trees
import pytest
from py_trees.common import Status

from behaviours.blackboard import seed
from behaviours.config import load_behaviour_config
from behaviours.context import Context, SimClock
from behaviours.skills.ask_question import AskAboutView
from core.events import EventLog
from mind.homeostasis import Homeostasis
from mind.personality import DRIVES, load_personality
from perception.detector.yolo import Detection
from robot.speaker import Speaker

FRAME = np.zeros((240, 320, 3), np.uint8)
PERSON = Detection("person", 0.9, (20.0, 40.0, 90.0, 230.0))   # on the left of the frame


class Fixed:
    """A question generator that proposes the same questions for every frame."""

    def __init__(self, questions: list[str]) -> None:
        self.questions = questions

    def ask(self, frame: np.ndarray, n: int) -> list[str]:
        return self.questions[:n]


def ask(questions: list[str], detections: list[Detection]) -> tuple[Status, list[dict]]:
    """Run the leaf once on a blank frame with these detections; status and events."""
    py_trees.blackboard.Blackboard.clear()
    clock = SimClock(dt=0.1)
    events = EventLog(None, clock)
    ctx = Context(robot=None, floor_plan=None, homeostasis=Homeostasis(load_personality()),
                  config=load_behaviour_config(), clock=clock, events=events,
                  speaker=Speaker(events), questions=Fixed(questions))
    seed(ctx, dict.fromkeys(DRIVES, 0.3), frame=FRAME, detections=detections)
    leaf = AskAboutView(ctx)
    leaf.tick_once()
    return leaf.status, events.events


@pytest.mark.parametrize(("detections", "said"), [
    ([], "is there a sofa ?"),                          # nobody seen: no question about people
    ([PERSON], "what is the man doing ?"),
])
def test_questions_about_people_need_a_person_in_view(detections, said):
    status, events = ask(["what is the man doing ?", "is there a sofa ?"], detections)
    assert status == Status.RUNNING
    assert [e["text"] for e in events if e["kind"] == "say"] == [said]


def test_unreadable_questions_are_never_said():
    status, events = ask(["sofa sofa the ?"], [])
    assert status == Status.FAILURE and events[-1]["kind"] == "no_question"


def test_with_no_question_left_it_says_where_it_sees_someone():
    status, events = ask([], [PERSON])
    remark = next(e for e in events if e["kind"] == "remark")
    assert remark["text"] == "I can see someone on my left." and status == Status.RUNNING
