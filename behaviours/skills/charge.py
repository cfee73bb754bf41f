"""Charge: ask for help, drive along a planned path to a pre-dock pose behind the dock, turn
to the dock's heading and drive straight in, plug in while the energy drive is relieved,
unplug and ask to be unplugged (docs/navigation.md). Interrupted, the base stops and the
charger is unplugged."""

from __future__ import annotations

import math
from collections.abc import Callable
from functools import cache
from itertools import pairwise
from typing import Any

import py_trees
from py_trees.common import Status

from behaviours.context import Context
from behaviours.obstacle_sensing import ObstacleSensing
from behaviours.skill import ContextBehaviour, Relieve, Say
from robot.geometry import Pose2D, wrap_angle
from robot.navigation import Navigator, Point
from robot.path_follower import PathFollower

ESCAPED_M = 0.02   # m: this close to the free cell where the path begins, the slide ends


def predock_pose(dock: Pose2D, distance: float) -> Pose2D:
    """The pose ``distance`` behind the dock pose (opposite to its facing), facing the dock."""
    return Pose2D(dock.x - distance * math.cos(dock.yaw), dock.y - distance * math.sin(dock.yaw),
                  dock.yaw)


class StopBase(ContextBehaviour):
    """A driving leaf: the base stops whenever the leaf ends (done, failed or interrupted)."""

    def terminate(self, new_status: Status) -> None:
        self.ctx.robot.base.set_velocity(0.0, 0.0, 0.0)


class FollowPath(StopBase):
    """Plan a path to ``goal`` and follow it; SUCCESS within the waypoint tolerance of the
    goal. The laser scanners (every tick) and the depth camera (its frames) report obstacles
    off the floor map; one of them on the path ahead means planning again (at most every
    ``replan_sensed_s``), and one near on the side the base moves to slows or stops its
    translation (:meth:`ObstacleSensing.guard`); being blocked or held for
    ``replan_blocked_s`` (or having no path) means planning again too. It never fails by
    itself (see :class:`Deadline`). A robot standing inside an inflated obstacle first
    slides through cells where its base fits to the free cell where the path begins,
    turning only so that a scanner looks the way it slides."""

    def __init__(self, name: str, ctx: Context, goal: Point,
                 sensing: Callable[[], ObstacleSensing]) -> None:
        super().__init__(name, ctx, reads=("depth", "frame_t"))
        self.goal = goal
        self._sensing = sensing
        self.navigator: Navigator | None = None   # set in setup(), with the follower
        self.sensing: ObstacleSensing | None = None
        self.follower: PathFollower | None = None
        self._stuck_since: float | None = None
        self._planned_at = -math.inf
        self._held = False
        self._has_path = False
        self._escape: list[Point] = []   # points to slide through, out of an inflation

    def setup(self, **kwargs: Any) -> None:
        """The planner on the floor map's occupancy grid, its sensors, and the follower."""
        self.sensing = self._sensing()
        self.navigator = self.sensing.navigator
        self.follower = self.ctx.path_follower()

    def _plan(self) -> None:
        x, y, _ = self.ctx.robot.base.pose()
        path = self.navigator.plan((x, y), self.goal)
        self._has_path = path is not None
        self._stuck_since = None
        self._planned_at = self.now
        if path is None:
            self.emit("no_path", start=[x, y], goal=list(self.goal))
            return
        grid = self.navigator.grid()
        first = next((k for k, q in enumerate(path) if grid.is_free(*q)), len(path) - 1)
        self._escape = path[:first + 1] if path[0] != (x, y) else []
        self.follower.start(path[first:])
        self.emit("path", waypoints=[[round(a, 3), round(b, 3)] for a, b in path],
                  length=round(sum(map(math.dist, path, path[1:])), 3))

    def initialise(self) -> None:
        self._held = False
        self._sense()
        self._plan()

    def _sense(self) -> None:
        self.sensing.update(self.now, self.bb.depth, self.bb.frame_t)

    def _path_ahead_clear(self) -> bool:
        """Whether the rest of the path, from where the robot is (through the points it
        slides through first, if it does), keeps clear of the obstacles sensed since it was
        planned (the cells around the robot itself excepted)."""
        grid = self.navigator.sensed_grid()
        rest = [self.ctx.robot.base.pose()[:2], *self._escape,
                *self.follower.path[self.follower.index:]]
        return grid.clear_ahead(rest[0], rest[1]) and all(
            grid.visible(a, b) for a, b in pairwise(rest[1:]))

    def update(self) -> Status:
        robot = self.ctx.robot
        self._sense()
        if self._has_path and self.follower.arrived(*robot.base.pose()[:2]):
            return Status.SUCCESS
        if (self._has_path and self.now - self._planned_at >= self.ctx.config.charge.replan_sensed_s
                and not self._path_ahead_clear()):
            self.emit("replan", pose=list(robot.base.pose()), reason="sensed")
            self._plan()
        if self._has_path and not robot.base.blocked and not self._held:
            self._stuck_since = None
        elif self._stuck_since is None:
            self._stuck_since = self.now
        elif self.now - self._stuck_since >= self.ctx.config.charge.replan_blocked_s:
            self.emit("replan", pose=list(robot.base.pose()), reason="blocked")
            self._plan()
        robot.base.set_velocity(*self._command())
        return Status.RUNNING

    def _command(self) -> tuple[float, float, float]:
        pose = self.ctx.robot.base.pose()
        if not self._has_path:
            return 0.0, 0.0, 0.0
        while self._escape and math.dist(pose[:2], self._escape[0]) <= ESCAPED_M:
            self._escape.pop(0)
        if self._escape:
            return self._guard(pose, self.follower.approach(pose, self._slide_pose(pose)))
        return self._guard(pose, self.follower.command(pose))

    def _slide_pose(self, pose: tuple[float, float, float]) -> Pose2D:
        """The next point of the slide, with the heading nearest the robot's own that has a
        laser scanner looking the way it slides: the base turns while it slides so as not
        to slide into its blind sectors (behind it, between the fans), and slides slower
        while it is still turning (:meth:`PathFollower.approach`)."""
        tx, ty = self._escape[0]
        way = math.atan2(ty - pose[1], tx - pose[0])
        facings = [math.radians(f) for f in self.ctx.robot.lasers.cfg.scanners.values()]
        yaw = min((wrap_angle(way - f) for f in facings),
                  key=lambda h: abs(wrap_angle(h - pose[2])))
        return Pose2D(tx, ty, yaw)

    def _guard(self, pose: tuple[float, float, float], command: tuple[float, float, float],
               ) -> tuple[float, float, float]:
        """``command`` as the sensed obstacles allow (:meth:`ObstacleSensing.guard`); being
        held counts as being blocked."""
        command, self._held = self.sensing.guard(pose, command)
        return command


class DockIn(StopBase):
    """Turn on the spot to the dock's heading, then drive straight in; SUCCESS (and a
    ``docked`` event) within ``dock_position_tolerance`` and ``dock_yaw_tolerance_deg``.
    The laser scanners watch the way in as on the path (:meth:`ObstacleSensing.guard`).
    Held back by something on the dock for ``replan_blocked_s``, it says so and asks for
    the way to be cleared, once (a ``dock_blocked`` event; people standing near it step
    back, :meth:`sim.world.World.make_way`), and keeps trying until the deadline."""

    def __init__(self, name: str, ctx: Context, dock: Pose2D,
                 sensing: Callable[[], ObstacleSensing]) -> None:
        super().__init__(name, ctx)
        self.dock = dock
        self._sensing = sensing
        self.follower: PathFollower | None = None   # set in setup(), with the sensing
        self.sensing: ObstacleSensing | None = None
        self._aligned = False
        self._held = False

    def setup(self, **kwargs: Any) -> None:
        self.follower = self.ctx.path_follower()
        self.sensing = self._sensing()

    def initialise(self) -> None:
        self.follower.reset()
        self._aligned = False
        self._blocked_since: float | None = None
        self._reported = False

    def _watch_blocked(self) -> None:
        cfg = self.ctx.config.charge
        if not (self.ctx.robot.base.blocked or self._held):
            self._blocked_since = None
            return
        self._blocked_since = self._blocked_since or self.now
        if not self._reported and self.now - self._blocked_since >= cfg.replan_blocked_s:
            self._reported = True
            self.emit("dock_blocked", pose=[round(v, 3) for v in self.ctx.robot.base.pose()])
            self.ctx.speaker.say(cfg.dock_blocked, behaviour=self.name)
            self.ctx.ask_way()

    def update(self) -> Status:
        cfg, robot = self.ctx.config.charge, self.ctx.robot
        self._watch_blocked()
        x, y, yaw = robot.base.pose()
        offset = math.hypot(self.dock.x - x, self.dock.y - y)
        yaw_error = abs(wrap_angle(self.dock.yaw - yaw))
        yaw_tolerance = math.radians(cfg.dock_yaw_tolerance_deg)
        if offset <= cfg.dock_position_tolerance and yaw_error <= yaw_tolerance:
            self.emit("docked", position_error=offset, yaw_error_deg=math.degrees(yaw_error))
            return Status.SUCCESS
        self._aligned = self._aligned or yaw_error <= yaw_tolerance
        vx, vy, wz = self.follower.approach((x, y, yaw), self.dock)
        self.sensing.update(self.now, None, -math.inf)
        command, self._held = self.sensing.guard((x, y, yaw), (vx, vy, wz) if self._aligned
                                                 else (0.0, 0.0, wz))
        robot.base.set_velocity(*command)
        return Status.RUNNING


class Deadline(py_trees.decorators.PassThrough):
    """Pass the child's status through, but FAILURE (and a ``dock_failed`` event) once it
    has been running ``timeout_s`` simulated seconds."""

    def __init__(self, name: str, child: py_trees.behaviour.Behaviour, ctx: Context,
                 timeout_s: float) -> None:
        super().__init__(name, child)
        self.ctx = ctx
        self.timeout_s = timeout_s
        self._deadline = 0.0

    def initialise(self) -> None:
        self._deadline = self.ctx.now + self.timeout_s

    def update(self) -> Status:
        if self.decorated.status == Status.RUNNING and self.ctx.now >= self._deadline:
            x, y, yaw = self.ctx.robot.base.pose()
            self.ctx.events.emit("dock_failed", behaviour=self.name, pose=[x, y, yaw],
                                 timeout_s=self.timeout_s)
            return Status.FAILURE
        return self.decorated.status


class PluggedIn(py_trees.decorators.PassThrough):
    """Charge while the child runs: plug in when it starts, unplug when it ends, fails or
    is interrupted."""

    def __init__(self, name: str, child: py_trees.behaviour.Behaviour, ctx: Context) -> None:
        super().__init__(name, child)
        self.ctx = ctx

    def initialise(self) -> None:
        self.ctx.robot.battery.start_charging()
        self.ctx.events.emit("charging", behaviour=self.name, battery=self.ctx.robot.battery.level)

    def terminate(self, new_status: Status) -> None:
        if self.ctx.robot.battery.charging:
            self.ctx.robot.battery.stop_charging()
            self.ctx.events.emit("unplugged", behaviour=self.name,
                                 battery=self.ctx.robot.battery.level,
                                 interrupted=new_status == Status.INVALID)


def approach(ctx: Context) -> py_trees.behaviour.Behaviour:
    """Drive to the pre-dock pose and dock, failing after ``charge.timeout_s``. Both driving
    leaves share one obstacle sensing (made in the first one's ``setup``), so what the
    scanners saw and track on the way is still known on the last straight."""
    cfg = ctx.config.charge
    dock = ctx.floor_plan.dock_pose()
    predock = predock_pose(dock, cfg.predock_distance)
    sensing = cache(lambda: ObstacleSensing.for_charge(ctx))
    steps = py_trees.composites.Sequence("Approach dock", memory=True, children=[
        FollowPath("Go to pre-dock", ctx, (predock.x, predock.y), sensing),
        DockIn("Dock in", ctx, dock, sensing)])
    return Deadline("Dock in time", steps, ctx, cfg.timeout_s)


def build(ctx: Context) -> py_trees.behaviour.Behaviour:
    """The charge subtree: ask, approach and dock, charge while relieving, ask to unplug."""
    cfg = ctx.config.charge
    return py_trees.composites.Sequence("Charge", memory=True, children=[
        Say("Ask to charge", ctx, cfg.ask),
        approach(ctx),
        PluggedIn("Plugged in", Relieve("Charge relieves", ctx, "charge"), ctx),
        Say("Ask to unplug", ctx, cfg.done)])
