"""Where bodies may start: the robot, the dock and the people of a scenario must not start
inside a wall or a piece of furniture (docs/scenarios.md, "Checks").

Each body is a disc on the floor: the robot (and its place on the dock) of radius
:data:`ROBOT_RADIUS`, a standing person of :data:`PERSON_RADIUS`. A seated person sits on a
seat (chair, armchair, sofa or bed), so only their centre is checked, against the furniture
one cannot sit on. Walls are the rooms' sides, :data:`WALL_THICKNESS` thick, open where a
door is. A problem names both bodies: ``robot.start: (2, 1.5) is inside the table 'dining'``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from sim.layout import Furniture, Placement, Room

ROBOT_RADIUS = 0.25    # m: Pepper's base is about 0.48 m wide
PERSON_RADIUS = 0.15   # m: a standing person's feet and legs
WALL_THICKNESS = 0.1   # m: as the world builds them
SEATS = ("chair", "armchair", "sofa", "bed")
Segment = tuple[tuple[float, float], tuple[float, float]]


def _door_gaps(room: Room, side: str) -> list[tuple[float, float]]:
    lo = room.x[0] if side in ("north", "south") else room.y[0]
    return [(lo + d.offset - d.width / 2, lo + d.offset + d.width / 2)
            for d in room.doors if d.wall == side]


def _split(a: float, b: float, gaps: list[tuple[float, float]]) -> list[tuple[float, float]]:
    pieces, start = [], a
    for g0, g1 in sorted(gaps):
        if g0 > start:
            pieces.append((start, g0))
        start = max(start, g1)
    return [*pieces, (start, b)] if start < b else pieces


def walls(rooms: Sequence[Room]) -> list[tuple[str, Segment]]:
    """Every wall piece as (``north wall of 'kitchen'``, segment); doors of either room that
    share a wall open it."""
    out: list[tuple[str, Segment]] = []
    for room in rooms:
        for side, (axis, at) in _sides(room).items():
            a, b = room.x if axis == "h" else room.y
            gaps = [g for other in rooms for other_side, (ax, o_at) in _sides(other).items()
                    if ax == axis and abs(o_at - at) < 1e-3
                    for g in _door_gaps(other, other_side)]
            for p0, p1 in _split(a, b, gaps):
                seg = ((p0, at), (p1, at)) if axis == "h" else ((at, p0), (at, p1))
                out.append((f"the {side} wall of {room.name!r}", seg))
    return out


def _sides(room: Room) -> dict[str, tuple[str, float]]:
    return {"south": ("h", room.y[0]), "north": ("h", room.y[1]),
            "west": ("v", room.x[0]), "east": ("v", room.x[1])}


def to_segment(x: float, y: float, seg: Segment) -> float:
    """Distance from ``(x, y)`` to the segment ``seg``."""
    (ax, ay), (bx, by) = seg
    dx, dy = bx - ax, by - ay
    t = max(0.0, min(1.0, ((x - ax) * dx + (y - ay) * dy) / (dx * dx + dy * dy or 1.0)))
    return math.hypot(x - ax - t * dx, y - ay - t * dy)


def _to_furniture(x: float, y: float, f: Furniture) -> float:
    """Distance from ``(x, y)`` to the footprint of ``f`` (0 inside it)."""
    yaw = math.radians(f.yaw)
    dx, dy = x - f.x, y - f.y
    u, v = math.cos(yaw) * dx + math.sin(yaw) * dy, -math.sin(yaw) * dx + math.cos(yaw) * dy
    depth, width, _ = f.dims
    return math.hypot(max(abs(u) - depth / 2, 0.0), max(abs(v) - width / 2, 0.0))


def overlaps(rooms: Sequence[Room], furniture: Sequence[Furniture], path: str, at: Placement,
             radius: float, seated: bool = False) -> list[str]:
    """What the disc of ``radius`` at ``at`` overlaps (walls, furniture), each problem as
    ``path: (x, y) is inside ...``; ``seated``: only the centre, and seats are allowed."""
    where = f"{path}: ({at.x:g}, {at.y:g})"
    out = [f"{where} is inside {name}" for name, seg in walls(rooms)
           if to_segment(at.x, at.y, seg) < radius + WALL_THICKNESS / 2]
    for f in furniture:
        if seated and f.type in SEATS:
            continue
        if _to_furniture(at.x, at.y, f) < (0.0 if seated else radius) or f.covers(at.x, at.y):
            out.append(f"{where} is inside the {f.type.replace('_', ' ')} {f.name!r}")
    return out
