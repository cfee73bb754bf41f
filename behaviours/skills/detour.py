"""Detours of the find-people skill: with furniture between the robot and the person it
follows, or the person turned away from the robot, drive around on the household's floor
map (docs/find_people.md).

The person's floor position is estimated from their box (:meth:`Steering.locate`). The
robot plans on the static occupancy grid of walls and furniture (the map knows no people) to
a free spot ``detour_distance_m`` from that estimate with a line of sight to it (or
``greet_max_m`` away where a table leaves no nearer room), the one cheapest to reach (path
length, plus the way around the person from the side the robot saw them from, plus the extra
distance), follows the path and turns to the estimate; there the visual approach takes over
again.
"""

from __future__ import annotations

import math

import numpy as np

from behaviours.context import Context
from robot.geometry import Footprint, Pose2D, wrap_angle
from robot.navigation import Navigator, OccupancyGrid, Point
from robot.path_follower import Velocity

FACING_TOLERANCE = math.radians(5.0)   # a detour ends once the robot faces the estimate so well
LOOK_SHORT_M = 0.4                     # lines of sight end this far before the estimate
SIGHT_CLEARANCE_M = 0.05               # ... and pass this close to walls and tall furniture
SIGHT_HEIGHT_M = 1.0                   # the camera (and a seated face) sees over furniture
                                       # lower than this: tables, chairs, sofas
PERSON_HALF_M = 0.4                    # the path keeps the robot's radius off this square
                                       # around the person's estimate (a seated person's knees)
NEAR_ARC_DEG = 30                      # a free spot 1 m from the person this close to the
                                       # robot's side of them: the robot can go and stand there
SNAP_M = 0.3                           # a path starting further than this from the robot
                                       # does not connect to where it stands


class Detour:
    """Plans and drives one detour at a time to a person's estimated position."""

    def __init__(self, ctx: Context) -> None:
        self.cfg = ctx.config.find_people
        charge = ctx.config.charge
        self.planner = Navigator(ctx.floor_plan, charge.grid_resolution,
                                 charge.robot_radius).planner
        plan = ctx.floor_plan
        tall = [f for f in plan.obstacles() if f.kind == "wall" or (
            f.kind == "furniture" and plan.furniture_top(f.name) > SIGHT_HEIGHT_M)]
        self.sight = OccupancyGrid.build(plan.room_bounds().values(), tall,
                                         charge.grid_resolution, SIGHT_CLEARANCE_M)
        self.follower = ctx.path_follower()
        self.target: Point | None = None    # the person's estimated position (None: a search goal)
        self.active = False
        self._turning = False

    def obstructed(self, robot: Point, person: Point) -> bool:
        """Whether the map has an obstacle on the straight way from ``robot`` to the spot
        ``detour_distance_m`` short of ``person``."""
        gap = math.dist(robot, person) - self.cfg.detour.distance_m
        if gap <= 0.0:
            return False
        f = gap / math.dist(robot, person)
        stop = (robot[0] + f * (person[0] - robot[0]), robot[1] + f * (person[1] - robot[1]))
        return not self.planner.grid.clear_ahead(robot, stop)

    def spots(self, person: Point) -> list[tuple[Point, float]]:
        """Free spots around ``person`` that have a line of sight to them on the map, with
        their distance: ``detour_distance_m`` away, and ``greet_max_m`` away on the sides
        where nothing nearer is free (across a table)."""
        grid, n = self.planner.grid, self.cfg.detour.candidates
        out = []
        for k in range(n):
            c, s = math.cos(math.tau * k / n), math.sin(math.tau * k / n)
            near = (person[0] + LOOK_SHORT_M * c, person[1] + LOOK_SHORT_M * s)
            for r in (self.cfg.detour.distance_m, self.cfg.detour.greet_max_m):
                spot = (person[0] + r * c, person[1] + r * s)
                if grid.is_free(*spot) and self.sight.visible(spot, near):
                    out.append((spot, r))
                    break
        return out

    def can_stand_near(self, robot: Point, person: Point) -> bool:
        """Whether the map has room for the robot ``detour_distance_m`` from ``person`` on
        its side of them: within ``NEAR_ARC_DEG`` of the line towards it (not, when a table
        stands between them)."""
        r = self.cfg.detour.distance_m
        if math.dist(robot, person) <= r:
            return True
        side = math.atan2(robot[1] - person[1], robot[0] - person[0])
        return any(self.planner.grid.is_free(person[0] + r * math.cos(side + a),
                                             person[1] + r * math.sin(side + a))
                   for a in np.radians(np.arange(-NEAR_ARC_DEG, NEAR_ARC_DEG + 1, 10)))

    def start(self, robot: Point, person: Point, front: float | None = None
              ) -> list[Point] | None:
        """Plan a detour towards ``person``; the path, or None when there is none. A spot
        costs its path length plus ``detour_arc_weight`` times the arc (m) around the person
        from their ``front`` (the world direction they look in, when the robot could tell),
        else from the robot's side: the robot saw them from there, so their front is likelier
        that way."""
        spots = self.spots(person)
        side = math.atan2(robot[1] - person[1], robot[0] - person[0]) if front is None else front
        costs = [self.cfg.detour.arc_weight * self.cfg.detour.distance_m * abs(wrap_angle(
            math.atan2(y - person[1], x - person[0]) - side)) + (r - self.cfg.detour.distance_m)
            for (x, y), r in spots]
        goal = self.planner.nearest_goal(robot, [spot for spot, _ in spots], costs)
        path = None if goal is None else self._plan(robot, goal, person)
        if path is not None:
            self.follower.start(path)
            self.target, self.active, self._turning = person, True, False
        return path

    def _plan(self, robot: Point, goal: Point, person: Point) -> list[Point] | None:
        """A path to ``goal`` that keeps off the person as the robot saw them (the map knows
        no people); where blocking them would cut the robot off from the goal (they stand in
        a narrow gap), the path on the map alone."""
        seen = Footprint("person", "person", person[0], person[1], 0.0, PERSON_HALF_M,
                         PERSON_HALF_M)
        path = self.planner.plan(robot, goal, self.planner.grid.with_obstacles([seen]))
        if path is None or math.dist(path[0], robot) > SNAP_M:
            path = self.planner.plan(robot, goal)
        return path

    def go(self, robot: Point, goal: Point) -> list[Point] | None:
        """Plan a way to ``goal`` on the map (to search somewhere else); the path, or None.
        It ends there, without turning to a person."""
        path = self.planner.plan(robot, goal)
        if path is not None:
            self.follower.start(path)
            self.target, self.active, self._turning = None, True, False
        return path

    def cancel(self) -> None:
        """Stop following the detour."""
        self.active = False

    def command(self, pose: tuple[float, float, float]) -> Velocity | None:
        """The base command along the detour, then turning to the estimate; None once the
        robot faces it (the detour is over)."""
        x, y, yaw = pose
        if not self._turning:
            if not self.follower.arrived(x, y):
                return self.follower.command(pose)
            self._turning = True
            self.follower.reset()
        if self.target is None:
            self.active = False
            return None
        heading = math.atan2(self.target[1] - y, self.target[0] - x)
        if abs(wrap_angle(heading - yaw)) <= FACING_TOLERANCE:
            self.active = False
            return None
        return self.follower.approach(pose, Pose2D(x, y, heading))
