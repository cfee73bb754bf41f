"""Geometry on the floor, in the world frame the robot's map uses: poses, headings and the
rectangles that obstacles take up."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple


def wrap_angle(angle: float) -> float:
    """``angle`` wrapped into [-pi, pi)."""
    return (angle + math.pi) % (2.0 * math.pi) - math.pi


class Pose2D(NamedTuple):
    """A position on the floor and a heading in radians (0 = facing +x); unpacks as a tuple."""

    x: float
    y: float
    yaw: float


@dataclass(frozen=True)
class Footprint:
    """An obstacle's rectangle on the floor: centre, heading (rad) and half extents."""

    name: str
    kind: str  # wall, furniture, object, dock or person
    x: float
    y: float
    yaw: float
    half_x: float
    half_y: float

    def corners(self) -> list[tuple[float, float]]:
        """The four corners, counter-clockwise."""
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        return [(self.x + c * dx - s * dy, self.y + s * dx + c * dy)
                for dx, dy in ((self.half_x, self.half_y), (-self.half_x, self.half_y),
                               (-self.half_x, -self.half_y), (self.half_x, -self.half_y))]

    def contains(self, x: float, y: float, margin: float = 0.0) -> bool:
        """Whether ``(x, y)`` is inside the rectangle grown by ``margin``."""
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        dx, dy = x - self.x, y - self.y
        return (abs(c * dx + s * dy) <= self.half_x + margin
                and abs(-s * dx + c * dy) <= self.half_y + margin)
