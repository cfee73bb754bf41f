"""The simulated omnidirectional base: velocity commands integrated in collision-checked
pieces (a piece that would push into another body is refused), on PyBullet."""

from __future__ import annotations

import math

import numpy as np
import pybullet as p

from robot.body import BaseConfig, Pose
from robot.geometry import wrap_angle


def yaw_quaternion(yaw: float) -> tuple[float, float, float, float]:
    """Quaternion (x, y, z, w) of a rotation by ``yaw`` about the vertical axis."""
    return (0.0, 0.0, math.sin(yaw / 2.0), math.cos(yaw / 2.0))


def bodies_near(client: int, body: int, centre: tuple[float, float], distance: float,
                angle: float, margin: float) -> set[int]:
    """Other bodies whose bounding boxes come within ``margin`` of the bounding box of
    ``body`` grown by what a move of ``distance`` and a turn of ``angle`` about
    ``centre`` can sweep."""
    boxes = [p.getAABB(body, link, physicsClientId=client)
             for link in range(-1, p.getNumJoints(body, physicsClientId=client))]
    low = np.min([b[0] for b in boxes], axis=0)
    high = np.max([b[1] for b in boxes], axis=0)
    c = np.asarray(centre)
    radius = float(np.hypot(*np.maximum(np.abs(low[:2] - c), np.abs(high[:2] - c))))
    pad = distance + angle * radius + margin
    found = p.getOverlappingObjects((low - pad).tolist(), (high + pad).tolist(),
                                    physicsClientId=client)
    return {b for b, _ in found or ()} - {body}


def moves_into(points: list[tuple], centre: tuple[float, float], dx: float, dy: float,
               dyaw: float) -> bool:
    """True when a move by (dx, dy, dyaw) about ``centre`` carries any of the robot's
    closest ``points`` (from ``getClosestPoints(robot, other)`` after the move) towards
    the other body, i.e. against the contact normal. Sliding along and leaving are fine."""
    for pt in points:
        rx, ry = pt[5][0] - centre[0], pt[5][1] - centre[1]     # the point on the robot
        ux, uy = dx - dyaw * ry, dy + dyaw * rx                 # its displacement
        if ux * pt[7][0] + uy * pt[7][1] < -1e-9:               # normal points B -> robot
            return True
    return False


class SimBase:
    """The base of the robot body ``body`` in the world ``client`` (:class:`robot.body.Base`);
    :meth:`advance` moves it once per simulation step."""

    def __init__(self, client: int, body: int, cfg: BaseConfig) -> None:
        self.client, self.body, self.cfg = client, body, cfg
        self._command = (0.0, 0.0, 0.0)
        self._blocked = False

    def set_velocity(self, vx: float, vy: float, wz: float) -> None:
        """Drive at (vx, vy) m/s in the robot's frame (x forward, y left) while turning at
        wz rad/s (counter-clockwise). The speed is clamped to the config's limits and the
        command holds until changed."""
        c = self.cfg
        speed = math.hypot(vx, vy)
        scale = min(1.0, c.max_linear_speed / speed) if speed > 0 else 0.0
        wz = min(max(wz, -c.max_angular_speed), c.max_angular_speed)
        self._command = (vx * scale, vy * scale, wz)

    def stop(self) -> None:
        """Stop the base."""
        self._command = (0.0, 0.0, 0.0)

    @property
    def velocity(self) -> tuple[float, float, float]:
        """The clamped (vx, vy, wz) command in force."""
        return self._command

    @property
    def blocked(self) -> bool:
        """True when an obstacle stopped (part of) the base motion in the last step."""
        return self._blocked

    def pose(self) -> Pose:
        """(x, y, yaw) of the base on the floor, in the world frame (m, m, rad)."""
        pos, orn = p.getBasePositionAndOrientation(self.body, physicsClientId=self.client)
        yaw = p.getEulerFromQuaternion(orn, physicsClientId=self.client)[2]
        return float(pos[0]), float(pos[1]), float(yaw)

    def set_pose(self, x: float, y: float, yaw: float) -> None:
        """Teleport the base (no collision check), e.g. when a scenario starts."""
        p.resetBasePositionAndOrientation(self.body, [x, y, 0.0], yaw_quaternion(yaw),
                                          physicsClientId=self.client)

    def advance(self, dt: float) -> tuple[float, float]:
        """Integrate the command over ``dt`` in collision-checked pieces; returns the
        distance driven and the angle turned. A piece the obstacles refuse is retried as
        pure translation, then as pure rotation; if all are refused the base stops."""
        vx, vy, wz = self._command
        self._blocked = False
        if vx == vy == wz == 0.0:
            return 0.0, 0.0
        c = self.cfg
        pieces = max(1, math.ceil(max(math.hypot(vx, vy) * dt / c.collision_step,
                                      abs(wz) * dt / c.collision_turn_step)))
        h = dt / pieces
        driven = turned = 0.0
        for _ in range(pieces):
            x, y, yaw = self.pose()
            heading = yaw + wz * h / 2.0    # midpoint rule: exact arcs in the limit
            dx = (vx * math.cos(heading) - vy * math.sin(heading)) * h
            dy = (vx * math.sin(heading) + vy * math.cos(heading)) * h
            full = (dx, dy, wz * h)
            tries = [m for m in dict.fromkeys([full, (dx, dy, 0.0), (0.0, 0.0, wz * h)]) if any(m)]
            moved = next((m for m in tries if self._try_move(x, y, yaw, *m)), None)
            self._blocked = self._blocked or moved != full
            if moved is None:
                break
            driven += math.hypot(moved[0], moved[1])
            turned += abs(moved[2])
        return driven, turned

    def _try_move(self, x: float, y: float, yaw: float, dx: float, dy: float,
                  dyaw: float) -> bool:
        """Move from (x, y, yaw) by (dx, dy, dyaw) unless, at the new pose, a point of
        the robot within the collision margin of another body is moving into it; returns
        whether it moved."""
        margin = self.cfg.collision_margin
        nearby = bodies_near(self.client, self.body, (x, y), math.hypot(dx, dy), abs(dyaw),
                             margin)
        self.set_pose(x + dx, y + dy, wrap_angle(yaw + dyaw))
        for other in nearby:
            points = p.getClosestPoints(self.body, other, margin, physicsClientId=self.client)
            if moves_into(points or [], (x + dx, y + dy), dx, dy, dyaw):
                self.set_pose(x, y, yaw)
                return False
        return True
