"""Decide: the policy picks each next action, a failed skill is followed by one stand-by,
and a critical battery pre-empts whatever runs for charging."""

from __future__ import annotations

import numpy as np
import py_trees
import pytest
from py_trees.common import Access, Status

from app.core.events import EventLog
from app.mind.homeostasis import Homeostasis
from app.mind.personality import DRIVES, load_personality
from behaviours.blackboard import seed
from behaviours.config import load_behaviour_config
from behaviours.context import Context, SimClock
from behaviours.decide import Decide


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
    ctx = Context(robot=None, world=None, homeostasis=Homeostasis(load_personality()),
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
