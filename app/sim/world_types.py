"""Small value types of the household world (app/sim/world.py): poses and footprints on the
floor, the lighting, and the social events a scenario's timeline hands to the robot's
senses."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

from app.sim.people import Rgb


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


@dataclass(frozen=True)
class Light:
    """TinyRenderer lighting; pass ``**light.camera_kwargs()`` to ``getCameraImage``."""

    direction: tuple[float, float, float]
    colour: Rgb
    ambient: float
    diffuse: float
    specular: float
    shadows: bool

    def camera_kwargs(self) -> dict[str, object]:
        """Keyword arguments for ``pybullet.getCameraImage``."""
        return {"lightDirection": list(self.direction), "lightColor": list(self.colour),
                "lightAmbientCoeff": self.ambient, "lightDiffuseCoeff": self.diffuse,
                "lightSpecularCoeff": self.specular, "shadow": int(self.shadows)}


@dataclass(frozen=True)
class SayEvent:
    """A person says ``text`` to ``to``: ``robot``, ``everyone`` or another person's name."""

    t: float
    person: str
    text: str
    to: str = "robot"


@dataclass(frozen=True)
class EncourageEvent:
    """A person encourages the robot (the thesis' encouragement stimulus) with ``text``."""

    t: float
    person: str
    text: str


@dataclass(frozen=True)
class EmotionEvent:
    """A person shows an emotion: ``happy``, ``sad`` or ``neutral``."""

    t: float
    person: str
    emotion: str


@dataclass(frozen=True)
class FeedbackEvent:
    """A person praises (``value`` +1) or scolds (-1) the robot, optionally naming the
    action it is ``about``."""

    t: float
    person: str
    value: int
    about: str | None


SocialEvent = SayEvent | EncourageEvent | EmotionEvent | FeedbackEvent
