"""The tick loop: a py_trees ``BehaviourTree`` that advances the simulation before each tick.

Every tree that runs in a simulated household (``companion run``, the skill harness, the
benchmarks) is ticked through :meth:`SimulationTree.run`, so the loop and the order within
one tick are written once: the simulation is shown what the robot is doing (people may react to it),
it steps, its social events go to the context's inbox (Sense reads them), the context's
clock moves to the simulation's time, then the tree ticks.
"""

from __future__ import annotations

from collections.abc import Callable
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

    def run(self, steps: int | None = None, seconds: float | None = None,
            until: Callable[[], bool] = lambda: False,
            after_tick: Callable[[], None] = lambda: None) -> float:
        """Tick ``steps`` times, or while fewer than ``seconds`` of simulated time have
        passed, or both; stop early once ``until()`` holds after a tick. ``after_tick`` runs
        after every tick (recording, scoring). Returns the simulated seconds it ran."""
        start, ticks = self.sim.t, 0
        while ((steps is None or ticks < steps)
               and (seconds is None or self.sim.t - start < seconds)):
            self.tick()
            ticks += 1
            after_tick()
            if until():
                break
        return self.sim.t - start

    def stop(self) -> None:
        """Stop the running behaviours (their ``terminate`` cleans up: base stopped,
        charger unplugged, standing posture commanded)."""
        self.root.stop(py_trees.common.Status.INVALID)
