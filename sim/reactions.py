"""People react to what the robot does: a person who likes or dislikes an action and sees
the robot doing it says so, as a line to the robot that its microphones hear like any
other.

People watch the robot, so the simulation is told what the robot is doing
(:meth:`sim.simulation.Simulation.show`); the robot itself learns of a reaction only
by hearing it. A person reacts at most once to each run of an action, once it has run
``after_s`` seconds and they are in the same room as the robot, at most ``distance_m`` from
it, with probability ``chance`` (seeded by the scenario's seed).
"""

from __future__ import annotations

import math

import numpy as np

from robot.percepts import SayEvent
from sim.scenario import Scenario
from sim.world import World

LINES = {   # what people say, one chosen at random each time
    "like": ("Well done, that was lovely!", "Good job, robot.", "I liked that, thank you."),
    "dislike": ("Stop that, please.", "Not now, please.", "Please don't do that."),
}


class Reactions:
    """The tastes of a scenario's people, turned into lines as the robot acts."""

    def __init__(self, scenario: Scenario) -> None:
        self.tastes = {p.name: p.tastes for p in scenario.people
                       if p.tastes.likes or p.tastes.dislikes}
        self.rng = np.random.default_rng([scenario.seed, 7])
        self.action: str | None = None
        self.since = 0.0
        self.done: set[str] = set()     # who has reacted to the current run of the action

    def show(self, t: float, action: str | None) -> None:
        """The robot is doing ``action`` at ``t`` (a change starts a new run of it)."""
        if action != self.action:
            self.action, self.since, self.done = action, t, set()

    def react(self, t: float, world: World, robot_xy: tuple[float, float]) -> list[SayEvent]:
        """The lines people say at ``t`` about what the robot is doing."""
        out: list[SayEvent] = []
        if self.action is None or t - self.since < 0:
            return out
        where = world.people_positions()
        for name, tastes in self.tastes.items():
            feeling = ("like" if self.action in tastes.likes
                       else "dislike" if self.action in tastes.dislikes else None)
            if (feeling is None or name in self.done or name not in where
                    or t - self.since < tastes.after_s):
                continue
            pose = where[name]
            near = math.hypot(pose.x - robot_xy[0], pose.y - robot_xy[1]) <= tastes.distance_m
            if not near or world.house.room_at(pose.x, pose.y) != world.house.room_at(*robot_xy):
                continue   # not seen yet: they may come and see it later in this run
            self.done.add(name)
            if self.rng.random() < tastes.chance:
                lines = LINES[feeling]
                out.append(SayEvent(t, name, lines[int(self.rng.integers(len(lines)))], "robot"))
        return out
