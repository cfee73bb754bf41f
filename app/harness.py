"""Run one skill subtree on its own in a household simulation (benchmarks and tests):
sense and the homeostasis tick run before it every step, as in the full tree."""

from __future__ import annotations

from collections.abc import Callable

import py_trees
from py_trees.common import Status

from behaviours.blackboard import seed
from behaviours.context import Context
from behaviours.homeostasis_tick import HomeostasisTick
from behaviours.sense import Sense
from behaviours.ticking import SimulationTree
from sim.simulation import Simulation


def skill_tree(sim: Simulation, ctx: Context, skill: py_trees.behaviour.Behaviour,
               action: str) -> SimulationTree:
    """``Sequence[Sense, Homeostasis, skill]`` ticked on ``sim``, with no decision: the
    blackboard is seeded from the scenario's initial drives and ``action`` runs."""
    seed(ctx, sim.scenario.robot.initial_drives(), action=action)
    return SimulationTree(py_trees.composites.Sequence(
        "skill", memory=False, children=[Sense(ctx), HomeostasisTick(ctx), skill]), sim, ctx)


def run_skill(sim: Simulation, ctx: Context, skill: py_trees.behaviour.Behaviour,
              action: str, max_seconds: float,
              after_tick: Callable[[], None] = lambda: None) -> tuple[Status, float]:
    """Tick ``skill`` as the running ``action`` until it succeeds or fails or ``max_seconds``
    of simulated time pass (``after_tick`` runs after every tick); returns its last status
    and the simulated seconds used."""
    tree = skill_tree(sim, ctx, skill, action)
    tree.setup()
    used = tree.run(seconds=max_seconds, after_tick=after_tick,
                    until=lambda: skill.status in (Status.SUCCESS, Status.FAILURE))
    status = skill.status
    if status == Status.RUNNING:
        tree.stop()
    return status, used
