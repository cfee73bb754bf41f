"""Where find people looks once a full turn in place has shown nobody it could greet.

The robot knows its home's floor map (rooms, walls, furniture; the map knows no people) and
remembers, for the rest of the run, where it located people and which rooms it last
searched in vain (blackboard ``people_seen`` and ``rooms_searched``). After a look around
it goes, in this order of preference:

1. to where it last saw someone, when that is at least ``revisit_min_m`` away, seen within
   ``sighting_memory_s`` and not a spot it gave up on; the most recent such place first;
2. to another room: one it has not searched, else the one searched longest ago (never the
   room it has just looked round in vain, so no empty room is searched twice in a row);
3. with no other room to go to, to another part of the room it is in: the free spot of the
   room farthest from here.

It walks there on a planned path (through doors), watching for people on the way, and
looks around again on arrival. docs/find_people.md explains the choices.
"""

from __future__ import annotations

import math

from behaviours.config import FindPeopleConfig
from behaviours.context import Context
from behaviours.skills.detour import Detour

Point = tuple[float, float]
Sighting = tuple[float, float, float]   # x, y (m, world) and when (simulated s)
SAME_PERSON_M = 1.0    # sightings closer than this are taken for the same person
WALL_MARGIN_M = 0.15   # a person's nearest surface is never this deep in a wall


def remember(seen: list[Sighting], spot: Point, now: float, keep: int) -> list[Sighting]:
    """``seen`` with a person located at ``spot`` now: older sightings of the same place
    replaced, the newest ``keep`` kept."""
    others = [s for s in seen if math.dist(s[:2], spot) >= SAME_PERSON_M]
    return [*others, (spot[0], spot[1], now)][-keep:]


class Search:
    """The look-around bookkeeping and the choice of where to search next."""

    def __init__(self, ctx: Context, detour: Detour) -> None:
        self.cfg: FindPeopleConfig = ctx.config.find_people
        self.rooms = ctx.floor_plan.room_bounds()
        self.walls = [f for f in ctx.floor_plan.obstacles() if f.kind == "wall"]
        self.detour = detour
        self.turned = 0.0     # rad turned in place since the robot last moved on

    def room_of(self, point: Point) -> str | None:
        """The room holding ``point`` on the map, or None."""
        return next((name for name, (x0, y0, x1, y1) in self.rooms.items()
                     if x0 <= point[0] <= x1 and y0 <= point[1] <= y1), None)

    def on_wall(self, point: Point) -> bool:
        """Whether ``point`` lies in a wall of the map (or within ``WALL_MARGIN_M`` of it):
        a person box located there is a false positive on the wall."""
        return any(f.contains(*point, WALL_MARGIN_M) for f in self.walls)

    def turn(self, wz: float, dt: float) -> bool:
        """Count a turn of ``wz`` (rad/s) for ``dt`` s; whether the robot has now looked
        all the way round."""
        self.turned += abs(wz) * dt
        return self.turned >= math.tau * self.cfg.search.look_around_turns

    def go_on(self, robot: Point, now: float, seen: list[Sighting],
              searched: dict[str, float], ignored: list[Point]) -> tuple[str, Point] | None:
        """Start walking to where to search next (see the module docstring): the reason
        ("last seen", "room", "elsewhere") and the goal, or None when no way is planned."""
        self.turned = 0.0
        cfg = self.cfg.search
        for x, y, t in sorted(seen, key=lambda s: -s[2]):
            if (now - t <= cfg.sighting_memory_s and math.dist(robot, (x, y)) >= cfg.revisit_min_m
                    and all(math.dist((x, y), i) >= SAME_PERSON_M for i in ignored)
                    and self.detour.start(robot, (x, y)) is not None):
                return "last seen", (x, y)
        here = self.room_of(robot)
        rooms = sorted((searched.get(name, -math.inf), math.dist(robot, _centre(b)), name)
                       for name, b in self.rooms.items() if name != here)
        for _, _, name in rooms:
            goal = _centre(self.rooms[name])
            if self.detour.go(robot, goal) is not None:
                return "room", goal
        if here is not None:
            goal = self._far_spot(robot, self.rooms[here])
            if goal is not None and self.detour.go(robot, goal) is not None:
                return "elsewhere", goal
        return None

    def _far_spot(self, robot: Point, bounds: tuple[float, float, float, float]
                  ) -> Point | None:
        """The free spot of the room (on a 1 m lattice) farthest from ``robot``, at least
        ``revisit_min_m`` away; None when there is none."""
        x0, y0, x1, y1 = bounds
        grid = self.detour.planner.grid
        spots = [(x0 + 0.5 + i, y0 + 0.5 + j) for i in range(int(x1 - x0))
                 for j in range(int(y1 - y0))]
        spots = [s for s in spots if grid.is_free(*s)
                 and math.dist(robot, s) >= self.cfg.search.revisit_min_m]
        return max(spots, key=lambda s: math.dist(robot, s), default=None)


def _centre(bounds: tuple[float, float, float, float]) -> Point:
    x0, y0, x1, y1 = bounds
    return (x0 + x1) / 2, (y0 + y1) / 2
