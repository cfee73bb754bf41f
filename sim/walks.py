"""People's walks in the simulated household: straight lines at a steady pace, stopping short
of whom they walk up to, and going round the robot rather than into it (docs/scenarios.md)."""

from __future__ import annotations

import math
from dataclasses import dataclass

Point = tuple[float, float]


@dataclass
class Walk:
    """A straight walk from ``start`` (at time ``t0``, facing ``yaw0``) to ``goal`` at
    ``speed`` m/s, turning to ``yaw_end`` on arrival if given."""

    t0: float
    start: Point
    yaw0: float
    goal: Point
    speed: float
    yaw_end: float | None
    walked0: float = 0.0   # m walked before this walk began (a walk that went round the robot)

    def at(self, t: float) -> tuple[float, float, float, float, bool]:
        """x, y, heading, distance walked (since ``walked0``) and whether arrived, at ``t``."""
        dx, dy = self.goal[0] - self.start[0], self.goal[1] - self.start[1]
        length = math.hypot(dx, dy)
        walked = min(max(t - self.t0, 0.0) * self.speed, length)
        f = walked / length if length > 1e-9 else 1.0
        done = walked >= length
        heading = math.atan2(dy, dx) if length > 1e-9 else self.yaw0
        if done and self.yaw_end is not None:
            heading = self.yaw_end
        return (self.start[0] + f * dx, self.start[1] + f * dy, heading, self.walked0 + walked,
                done)


def short_of(here: Point, target: Point, stop_m: float) -> tuple[Point, float]:
    """Where a walk from ``here`` towards ``target`` stops, ``stop_m`` short of it (or
    ``here`` when already that close), and the heading that faces ``target``."""
    dx, dy = target[0] - here[0], target[1] - here[1]
    dist = math.hypot(dx, dy)
    f = max(dist - stop_m, 0.0) / dist if dist > 1e-9 else 0.0
    return (here[0] + f * dx, here[1] + f * dy), math.atan2(dy, dx)


def give_way(here: Point, there: Point, goal: Point, robot: Point, keep: float) -> Point | None:
    """Where a walker stepping from ``here`` to ``there`` on the way to ``goal`` steps
    instead so as not to come within ``keep`` of ``robot``: the same step length along the
    circle round it through ``here``, on the side the step was going, or ``here`` (they stop
    short) when the goal itself is that close to the robot. None when the step keeps clear,
    or does not come nearer."""
    hx, hy = here[0] - robot[0], here[1] - robot[1]
    tx, ty = there[0] - robot[0], there[1] - robot[1]
    near, now = math.hypot(tx, ty), math.hypot(hx, hy)
    if near >= keep or near >= now or now < 1e-9:
        return None
    if math.dist(goal, robot) < keep:
        return here
    side = 1.0 if hx * (ty - hy) - hy * (tx - hx) >= 0 else -1.0   # counter-clockwise or not
    angle = math.atan2(hy, hx) + side * math.dist(here, there) / now
    return robot[0] + now * math.cos(angle), robot[1] + now * math.sin(angle)
