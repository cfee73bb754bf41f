"""Decide: the policy picks each next action, a failed skill is followed by one stand-by,
a critical battery pre-empts whatever runs for charging, a line said to the robot pre-empts
the policy's choice (not a critical charge), and a reply's request runs next, once."""

from __future__ import annotations

import numpy as np
import py_trees
import pytest
from py_trees.common import Access, Status

from behaviours.blackboard import seed
from behaviours.config import load_behaviour_config
from behaviours.context import Context, SimClock
from behaviours.decide import Decide
from behaviours.listening import Promise
from core.events import EventLog
from dialogue.manager import DialogueManager
from dialogue.qa.base import Action
from dialogue.qa.bot import QABot
from mind.homeostasis import Homeostasis
from mind.personality import DRIVES, load_personality
from robot.percepts import HeardLine
from robot.speaker import Speaker


class Always:
    """A policy that always wants one action."""

    def __init__(self, action: str) -> None:
        self.action = action

    def act(self, motivations: np.ndarray) -> str:
        return self.action


@pytest.fixture
def setup():
    py_trees.blackboard.Blackboard.clear()
    clock = SimClock(dt=0.1)
    ctx = Context(robot=None, floor_plan=None, homeostasis=Homeostasis(load_personality()),
                  config=load_behaviour_config(), clock=clock, events=EventLog(None, clock),
                  speaker=None)
    seed(ctx, dict.fromkeys(DRIVES, 0.5))
    decide = Decide(ctx, Always("find_people"))
    bb = py_trees.blackboard.Client(name="test")
    for key in ("motivations", "drives", "act_status", "action"):
        bb.register_key(key, access=Access.WRITE)
    bb.motivations, bb.drives = np.full(6, 0.5), np.full(6, 0.5)
    decide.update()
    return decide, bb, ctx


def finish(decide: Decide, bb, status: Status) -> str:
    """End the running action with ``status``; the action Decide starts next."""
    bb.act_status = status
    decide.update()
    return bb.action


def test_a_failed_skill_is_followed_by_one_stand_by(setup):
    decide, bb, ctx = setup
    assert bb.action == "find_people"
    bb.act_status = Status.RUNNING
    decide.update()
    assert bb.action == "find_people"  # nothing new while the skill runs
    assert finish(decide, bb, Status.FAILURE) == "stand_by"
    assert finish(decide, bb, Status.SUCCESS) == "find_people"
    reasons = [e["reason"] for e in ctx.events.of_kind("action")]
    assert reasons == ["policy", "find_people failed", "policy"]


def test_critical_energy_preempts_for_charging(setup):
    decide, bb, ctx = setup
    bb.act_status = Status.RUNNING
    bb.drives = np.array([ctx.config.preempt_energy, 0.5, 0.5, 0.5, 0.5, 0.5])
    decide.update()
    assert bb.action == "charge"
    assert ctx.events.of_kind("preempted")[0]["action"] == "find_people"
    assert finish(decide, bb, Status.RUNNING) == "charge"  # not pre-empted again


def line(ctx, text: str = "What time is it?", promised: bool = False, n: int = 1):
    """Line ``n``, heard now from straight ahead."""
    return HeardLine(n, ctx.now, "Grace", text, "robot", 0.0, promised=promised)


@pytest.fixture
def listening(setup):
    decide, bb, ctx = setup
    for key in ("heard", "request", "stimuli"):
        bb.register_key(key, access=Access.WRITE)
    return decide, bb, ctx


def test_a_line_said_to_the_robot_preempts_the_policys_choice(listening):
    decide, bb, ctx = listening
    bb.act_status = Status.RUNNING
    bb.heard = [line(ctx)]
    decide.update()
    assert bb.action == "chat"
    assert ctx.events.of_kind("preempted")[-1] == {**ctx.events.of_kind("preempted")[-1],
                                                   "action": "find_people",
                                                   "reason": "spoken to"}
    bb.heard = []
    assert finish(decide, bb, Status.SUCCESS) == "find_people"  # back to the policy


def test_a_critical_charge_is_not_interrupted_and_the_line_is_answered_after(listening):
    decide, bb, ctx = listening
    bb.act_status = Status.RUNNING
    bb.drives = np.array([ctx.config.preempt_energy, 0.5, 0.5, 0.5, 0.5, 0.5])
    decide.update()
    assert bb.action == "charge"
    bb.drives = np.full(6, 0.5)
    bb.heard = [line(ctx, promised=True)]
    assert finish(decide, bb, Status.RUNNING) == "charge"
    ctx.clock.t += 3600.0  # a promised line never expires
    assert finish(decide, bb, Status.SUCCESS) == "chat"


def test_a_request_starts_its_action_once(listening):
    decide, bb, _ = listening
    bb.request = Action("sing_dance", {"song": "Happy Birthday"})
    assert finish(decide, bb, Status.SUCCESS) == "sing_dance"
    assert finish(decide, bb, Status.SUCCESS) == "find_people"
    assert bb.request is None


def test_during_a_critical_charge_each_new_speaker_gets_one_promise(listening):
    decide, bb, ctx = listening
    ctx.speaker = Speaker(ctx.events)
    promise = Promise(ctx)
    bb.act_status = Status.RUNNING
    bb.drives = np.array([ctx.config.preempt_energy, 0.5, 0.5, 0.5, 0.5, 0.5])
    decide.update()
    bb.heard = [line(ctx)]
    promise.update()
    promise.update()
    said = ctx.events.of_kind("say")
    assert len(said) == 1 and "charge my battery" in said[0]["text"] and said[0]["lines"] == [1]
    assert all(x.promised for x in bb.heard)
    bb.drives = np.full(6, 0.5)
    assert finish(decide, bb, Status.SUCCESS) == "chat"
    bb.heard = [line(ctx, "Hello?")]
    promise.update()
    assert len(ctx.events.of_kind("say")) == 1  # a chat may be interrupted: no promise


def test_during_a_critical_charge_lines_are_answered_at_once_and_songs_promised(listening,
                                                                                 tmp_path):
    decide, bb, ctx = listening
    ctx.speaker = Speaker(ctx.events)
    ctx.dialogue = DialogueManager(QABot.offline(out_dir=tmp_path))
    promise = Promise(ctx)
    bb.act_status = Status.RUNNING
    bb.drives = np.array([ctx.config.preempt_energy, 0.5, 0.5, 0.5, 0.5, 0.5])
    decide.update()
    bb.heard = [line(ctx, "What time is it?"), line(ctx, "Can you sing Happy Birthday?", n=2)]
    promise.update()
    said = ctx.events.of_kind("say")
    assert len(said) == 1 and said[0]["line"] == 1 and said[0]["in_reply_to"] == "What time is it?"
    promise.update()                      # still saying the first reply
    assert len(ctx.events.of_kind("say")) == 1
    ctx.clock.t += 10.0
    promise.update()
    song = ctx.events.of_kind("say")[-1]
    assert song["in_reply_to"] == "Can you sing Happy Birthday?"
    assert song["text"].endswith("I'll do it right after I charge my battery.")
    assert bb.heard == [] and bb.request.name == "sing_dance"
    assert finish(decide, bb, Status.RUNNING) == "charge"     # the charge goes on
    bb.drives = np.full(6, 0.5)
    assert finish(decide, bb, Status.SUCCESS) == "sing_dance"
