"""The tick loop: a py_trees ``BehaviourTree`` that advances the simulation before each tick.

Every tree that runs in a simulated household (``companion run``, the skill harness, the
benchmarks) is ticked through :class:`SimulationTree`, so the order within one tick is
written once: the simulation is shown what the robot is doing (people may react to it),
it steps, its social events go to the context's inbox (Sense reads them), the context's
clock moves to the simulation's time, then the tree ticks.
"""

from __future__ import annotations

from typing import Any

import py_trees

from behaviours.context import Context


class SimulationTree(py_trees.trees.BehaviourTree):
    """``root`` ticked on ``sim`` (an :class:`sim.simulation.Simulation`): each
    :meth:`tick` first steps the simulation by one scenario step (the pre-tick handler
    :meth:`advance`). :meth:`setup` sets up every behaviour once (the heavy one-time work:
    planners, grids, routines); call it before the first tick."""

    def __init__(self, root: py_trees.behaviour.Behaviour, sim: Any, ctx: Context) -> None:
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
