"""Run one skill subtree on its own in a household simulation (benchmarks and tests):
sense and the homeostasis tick run before it every step, as in the full tree."""

from __future__ import annotations

import py_trees
from py_trees.common import Status

from app.sim.simulation import Simulation
from behaviours.context import Household
from behaviours.homeostasis_tick import HomeostasisTick
from behaviours.sense import Sense


def skill_root(house: Household, skill: py_trees.behaviour.Behaviour,
               initial_drives: dict[str, float]) -> py_trees.composites.Sequence:
    """``Sequence[Sense, Homeostasis, skill]`` (no decision: the action is fixed)."""
    return py_trees.composites.Sequence(
        "skill", memory=False,
        children=[Sense(house), HomeostasisTick(house, initial_drives), skill])


def run_skill(sim: Simulation, house: Household, skill: py_trees.behaviour.Behaviour,
              action: str, max_seconds: float) -> tuple[Status, float]:
    """Tick ``skill`` as the running ``action`` until it succeeds or fails or ``max_seconds``
    of simulated time pass; returns its last status and the simulated seconds used."""
    root = skill_root(house, skill, sim.scenario.robot.initial_drives())
    bb = py_trees.blackboard.Client(name="harness")
    for key in ("action", "relieving", "tracking"):
        bb.register_key(key, access=py_trees.common.Access.WRITE)
    bb.action, bb.relieving, bb.tracking = action, False, 0.0
    start = sim.t
    root.setup_with_descendants()
    while sim.t - start < max_seconds:
        house.inbox.extend(sim.step())
        house.clock.t = sim.t
        root.tick_once()
        if skill.status in (Status.SUCCESS, Status.FAILURE):
            break
    status = skill.status
    if status == Status.RUNNING:
        root.stop(Status.INVALID)
    return status, sim.t - start
