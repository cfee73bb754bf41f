"""The static household of a scenario: rooms with their doors, furniture and objects, and
the small types they share (docs/scenarios.md). :mod:`sim.scenario` puts people, the
robot and the timeline into it.

Conventions: metres and seconds; x east, y north; yaw in DEGREES in the YAML (0 = facing +x,
90 = facing +y); colours as ``"#rrggbb"``.
"""

from __future__ import annotations

import math
import re
from typing import Annotated, Literal

from pydantic import AfterValidator, Field, model_validator

from core.config_files import StrictModel

Unit = Annotated[float, Field(ge=0, le=1)]
Positive = Annotated[float, Field(gt=0)]
PoseName = Literal["standing", "sitting", "arms_raised"]
FurnitureType = Literal["table", "coffee_table", "cake_table", "chair", "armchair", "sofa",
                        "bed", "shelf", "tv", "plant"]
ObjectType = Literal["duck", "teddy", "tray", "sphere", "mug", "cake", "ball", "book", "plate"]
# Default (depth, width, height) in metres of each furniture type; its front faces +x.
FURNITURE_SIZES: dict[str, tuple[float, float, float]] = {
    "table": (0.8, 1.2, 0.75), "coffee_table": (0.55, 1.0, 0.42), "cake_table": (1.0, 1.0, 0.75),
    "chair": (0.45, 0.45, 0.9), "armchair": (0.85, 0.85, 0.9), "sofa": (0.9, 2.0, 0.85),
    "bed": (2.0, 1.4, 0.55), "shelf": (0.35, 0.9, 1.8), "tv": (0.45, 1.2, 1.15),
    "plant": (0.4, 0.4, 1.1),
}
_HEX = re.compile(r"^#[0-9a-fA-F]{6}$")
ROOM_MARGIN = 0.15  # people and targets keep this far from a room's walls


def _colour(value: str) -> str:
    if not _HEX.match(value):
        raise ValueError(f"expected a colour like '#3a7bd5', got {value!r}")
    return value.lower()


Colour = Annotated[str, AfterValidator(_colour)]


def rgb(colour: str) -> tuple[float, float, float]:
    """``"#rrggbb"`` as an RGB triple in [0, 1]."""
    return tuple(int(colour[i:i + 2], 16) / 255 for i in (1, 3, 5))  # type: ignore[return-value]


class Placement(StrictModel):
    """A floor position and heading (yaw in degrees)."""

    x: float
    y: float
    yaw: float = 0.0


class Door(StrictModel):
    """A gap in one wall; ``offset`` is from the wall's west (or south) end to the door centre."""

    name: str
    wall: Literal["north", "south", "east", "west"]
    offset: Positive
    width: float = Field(default=0.9, gt=0.3, le=3)


class RoomNoise(StrictModel):
    """A room's background sound (sim/acoustics.py): a steady ``level_db`` (dB SPL) all
    over the room, and optionally a ``source`` (a furniture item's name, e.g. the TV)
    playing at ``source_db`` one metre in front of it."""

    level_db: float = Field(default=30.0, ge=0, le=90)
    source: str | None = None
    source_db: float = Field(default=60.0, ge=0, le=100)


class Room(StrictModel):
    """An axis-aligned rectangular room with walls on all four sides and optional doors."""

    name: str
    kind: str | None = None   # for the question generator's ground truth (docs/scenarios.md)
    x: tuple[float, float]
    y: tuple[float, float]
    wall_height: float = Field(default=2.5, gt=0.5, le=5)
    wall_colour: Colour = "#e8e2d6"
    floor_colour: Colour = "#b89a74"
    ceiling: bool = True
    doors: tuple[Door, ...] = ()
    noise: RoomNoise = RoomNoise()

    @model_validator(mode="after")
    def _geometry(self) -> Room:
        if self.x[1] - self.x[0] < 1 or self.y[1] - self.y[0] < 1:
            raise ValueError("x and y must be [min, max] with max - min >= 1 m")
        for door in self.doors:
            length = self.x[1] - self.x[0] if door.wall in ("north", "south") else \
                self.y[1] - self.y[0]
            if door.offset - door.width / 2 < 0 or door.offset + door.width / 2 > length:
                raise ValueError(f"door {door.name!r} does not fit in the {door.wall} wall "
                                 f"({length:g} m long)")
        return self

    def contains(self, x: float, y: float, margin: float = 0.0) -> bool:
        """Whether ``(x, y)`` lies inside the room, at least ``margin`` from its walls."""
        return (self.x[0] + margin <= x <= self.x[1] - margin
                and self.y[0] + margin <= y <= self.y[1] - margin)


class Furniture(StrictModel):
    """A piece of furniture built from primitives; its front faces ``yaw``."""

    name: str
    type: FurnitureType
    x: float
    y: float
    yaw: float = 0.0
    size: tuple[Positive, Positive, Positive] | None = None  # depth, width, height
    colour: Colour | None = None

    @property
    def dims(self) -> tuple[float, float, float]:
        """(depth, width, height) in metres: ``size`` or the type's default."""
        return self.size or FURNITURE_SIZES[self.type]

    def covers(self, x: float, y: float) -> bool:
        """Whether the floor point ``(x, y)`` lies under this piece of furniture."""
        yaw = math.radians(self.yaw)
        dx, dy = x - self.x, y - self.y
        depth, width, _ = self.dims
        return (abs(math.cos(yaw) * dx + math.sin(yaw) * dy) <= depth / 2
                and abs(-math.sin(yaw) * dx + math.cos(yaw) * dy) <= width / 2)


class SceneObject(StrictModel):
    """A small object, on the floor or on top of the furniture named by ``on_top_of``."""

    name: str | None = None
    type: ObjectType
    x: float | None = None
    y: float | None = None
    on_top_of: str | None = None
    yaw: float = 0.0
    scale: float = Field(default=1.0, gt=0, le=5)
    colour: Colour | None = None
    candles: int = Field(default=0, ge=0, le=30)
    lit: bool = True

    @model_validator(mode="after")
    def _placed(self) -> SceneObject:
        if self.on_top_of is None and (self.x is None or self.y is None):
            raise ValueError("give x and y, or `on_top_of` (a furniture name)")
        return self
