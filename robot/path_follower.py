"""The PID path follower of the omnidirectional base (docs/navigation.md): two simple-pid
controllers, heading error -> turn rate and remaining distance -> forward speed, the speed
cut while the heading error is large; it drives along the paths of
:class:`robot.navigation.Planner`, or onto a final pose."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Protocol

from simple_pid import PID

from robot.geometry import Pose2D, wrap_angle

Point = tuple[float, float]
Velocity = tuple[float, float, float]             # vx, vy (robot frame, m/s), wz (rad/s)


class Gains(Protocol):
    """Gains of one PID controller."""

    kp: float
    ki: float
    kd: float


class FollowerConfig(Protocol):
    """The path follower's parameters (behaviour.yaml's ``pid`` section)."""

    heading: Gains
    distance: Gains
    slowdown_heading_deg: float
    lookahead_m: float


class PathFollower:
    """Velocity commands that drive the base along waypoints, or onto a final pose.

    The heading controller turns towards a carrot ``lookahead_m`` ahead of the robot's
    projection on the current leg (so the robot comes back onto the leg after a deviation);
    its measurement is the unwrapped yaw so that its derivative never jumps at +-pi. The
    distance controller sets the forward speed from the distance left along the path, and
    the speed is scaled by ``1 - |heading error| / slowdown_heading_deg`` (zero beyond:
    turn on the spot). A waypoint within ``tolerance`` counts as passed.
    """

    def __init__(self, gains: FollowerConfig, max_speed: float, max_turn: float,
                 tolerance: float, clock: Callable[[], float]) -> None:
        h, d = gains.heading, gains.distance
        self.turn_pid = PID(h.kp, h.ki, h.kd, sample_time=None, time_fn=clock,
                            output_limits=(-max_turn, max_turn))
        self.speed_pid = PID(d.kp, d.ki, d.kd, setpoint=0.0, sample_time=None, time_fn=clock,
                             output_limits=(0.0, max_speed))
        self.slowdown = math.radians(gains.slowdown_heading_deg)
        self.lookahead = gains.lookahead_m
        self.tolerance = tolerance
        self.path: list[Point] = []
        self.index = 0
        self._yaw: float | None = None      # last measured yaw
        self._unwrapped = 0.0

    def start(self, path: Sequence[Point]) -> None:
        """Follow ``path`` (its first point is where the robot starts) from the beginning."""
        self.path = list(path)
        self.index = min(1, len(self.path) - 1)
        self.reset()

    def reset(self) -> None:
        """Forget the controllers' history (a new path or a new kind of motion)."""
        self.turn_pid.reset()
        self.speed_pid.reset()
        self._yaw = None

    @property
    def goal(self) -> Point:
        """The last waypoint."""
        return self.path[-1]

    def remaining(self, x: float, y: float) -> float:
        """Distance (m) from (x, y) through the waypoints still ahead to the goal."""
        rest = self.path[self.index:]
        return math.dist((x, y), rest[0]) + sum(map(math.dist, rest, rest[1:]))

    def arrived(self, x: float, y: float) -> bool:
        """Whether (x, y) is within the tolerance of the goal."""
        return math.dist((x, y), self.goal) <= self.tolerance

    def carrot(self, x: float, y: float) -> Point:
        """The point ``lookahead`` ahead of (x, y)'s projection on the current leg, at most
        the leg's end (the current waypoint)."""
        (ax, ay), (bx, by) = self.path[max(self.index - 1, 0)], self.path[self.index]
        length = math.hypot(bx - ax, by - ay)
        if length < 1e-9:
            return bx, by
        along = ((x - ax) * (bx - ax) + (y - ay) * (by - ay)) / length + self.lookahead
        f = min(max(along / length, 0.0), 1.0)
        return ax + f * (bx - ax), ay + f * (by - ay)

    def _steer(self, yaw: float, heading: float) -> tuple[float, float]:
        """Turn rate towards ``heading`` and the heading error (rad)."""
        turned = 0.0 if self._yaw is None else wrap_angle(yaw - self._yaw)
        self._unwrapped = yaw if self._yaw is None else self._unwrapped + turned
        self._yaw = yaw
        error = wrap_angle(heading - yaw)
        self.turn_pid.setpoint = self._unwrapped + error
        return self.turn_pid(self._unwrapped), error

    def _speed(self, distance: float, heading_error: float) -> float:
        """Forward speed for ``distance`` left, cut while the heading is off."""
        speed = self.speed_pid(-distance)       # error = setpoint 0 - (-distance) = distance
        return speed * max(0.0, 1.0 - abs(heading_error) / self.slowdown)

    def command(self, pose: tuple[float, float, float]) -> Velocity:
        """(vx, 0, wz) along the path; zero once the goal is reached."""
        x, y, yaw = pose
        if self.arrived(x, y):
            return 0.0, 0.0, 0.0
        while self.index < len(self.path) - 1 and math.dist((x, y), self.path[self.index]) \
                <= self.tolerance:
            self.index += 1
        tx, ty = self.carrot(x, y)
        wz, error = self._steer(yaw, math.atan2(ty - y, tx - x))
        return self._speed(self.remaining(x, y), error), 0.0, wz

    def approach(self, pose: tuple[float, float, float], target: Pose2D) -> Velocity:
        """Holonomic final approach: turn towards ``target.yaw`` while sliding straight onto
        the target position (slower while the heading is off, as in :meth:`command`)."""
        x, y, yaw = pose
        wz, error = self._steer(yaw, target.yaw)
        dx, dy = target.x - x, target.y - y
        distance = math.hypot(dx, dy)
        speed = self._speed(distance, error)
        if distance < 1e-9:
            return 0.0, 0.0, wz
        c, s = math.cos(yaw), math.sin(yaw)
        return speed * (c * dx + s * dy) / distance, speed * (-s * dx + c * dy) / distance, wz
