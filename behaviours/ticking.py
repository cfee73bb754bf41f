"""The tick loop: a py_trees ``BehaviourTree`` that advances the simulation before each tick.

Every tree that runs in a simulated household (``companion run``, the skill harness, the
benchmarks) is ticked through :class:`SimulationTree`, so the order within one tick is
written once: the simulation is shown what the robot is doing (people may react to it),
it steps, its social events go to the context's inbox (Sense reads them), the context's
clock moves to the simulation's time, then the tree ticks.
"""

from __future__ import annotations

from typing import Protocol

import py_trees

from behaviours.context import Context
from robot.percepts import SocialEvent, Sound


class Household(Protocol):
    """Where the robot lives, stepped once per tick: ``sim.simulation.Simulation``, or a
    real household's sensors gathered over the same period."""

    t: float

    def show(self, action: str | None) -> None:
        """What the robot is doing now, for the people around it to react to."""
        ...

    def step(self) -> list[SocialEvent | Sound]:
        """Advance by one step; the social events and recordings that came in."""
        ...


class SimulationTree(py_trees.trees.BehaviourTree):
    """``root`` ticked on ``sim`` (a :class:`Household`): each
    :meth:`tick` first steps the simulation by one scenario step (the pre-tick handler
    :meth:`advance`). :meth:`setup` sets up every behaviour once (the heavy one-time work:
    planners, grids, routines); call it before the first tick."""

    def __init__(self, root: py_trees.behaviour.Behaviour, sim: Household, ctx: Context) -> None:
        super().__init__(root)
        self.sim, self.ctx = sim, ctx
        self.add_pre_tick_handler(self.advance)

    def advance(self, tree: py_trees.trees.BehaviourTree) -> None:
        """Show the simulation the running action; step it; its social events to the inbox;
        the clock to its time."""
        self.sim.show(py_trees.blackboard.Blackboard.storage.get("/action"))
        self.ctx.inbox.extend(self.sim.step())
        self.ctx.clock.t = self.sim.t

    def stop(self) -> None:
        """Stop the running behaviours (their ``terminate`` cleans up: base stopped,
        charger unplugged, standing posture commanded)."""
        self.root.stop(py_trees.common.Status.INVALID)
