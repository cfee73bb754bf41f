"""Furniture and small objects of the household, built from primitives (boxes, cylinders,
spheres) or taken from ``pybullet_data`` models: the parts of each furniture kind, the URDF
of each object, and their default colours. Shared by the world (sim/world.py) and the
renderers of the detector's and VQG's training data.
"""

from __future__ import annotations

import math

from sim.layout import SceneObject
from sim.people import Part, Rgb, joint_xml, link_xml

FURNITURE_COLOURS: dict[str, str] = {
    "table": "#8b5a2b", "coffee_table": "#6b4226", "cake_table": "#f4f0ff", "chair": "#9c6b3c",
    "armchair": "#7a3b3b", "sofa": "#4a5d7a", "bed": "#a07850", "shelf": "#b08850",
    "tv": "#3b3b3b", "plant": "#b5651d",
}
DARK: Rgb = (0.08, 0.08, 0.1)


def _legs(d: float, w: float, h: float, c: Rgb, r: float = 0.025) -> list[Part]:
    return [Part("cylinder", (r, h), c, (sx * (d / 2 - 2 * r), sy * (w / 2 - 2 * r), h / 2))
            for sx in (1, -1) for sy in (1, -1)]


def _upholstered(d: float, w: float, h: float, c: Rgb, seat: float) -> tuple[list[Part], float]:
    """Seat block, back and two arms (armchair, sofa)."""
    back, arm = min(0.2, d / 4), seat + 0.2
    return [Part("box", (d, w, seat), c, (0, 0, seat / 2)),
            Part("box", (back, w, h), c, (-d / 2 + back / 2, 0, h / 2)),
            *[Part("box", (d, 0.15, arm), c, (0, s * (w / 2 - 0.075), arm / 2)) for s in (1, -1)]
            ], seat


def furniture_parts(kind: str, d: float, w: float, h: float, c: Rgb) -> tuple[list[Part], float]:
    """Primitive parts of a furniture item (front facing +x) and the height of its top surface."""
    dark = (c[0] * 0.6, c[1] * 0.6, c[2] * 0.6)
    if kind in ("table", "coffee_table"):
        return [Part("box", (d, w, 0.04), c, (0, 0, h - 0.02)), *_legs(d, w, h - 0.04, dark)], h
    if kind == "cake_table":
        return [Part("cylinder", (w / 2, 0.03), c, (0, 0, h - 0.015)),
                Part("cylinder", (0.06, h - 0.03), (0.5, 0.5, 0.5), (0, 0, (h - 0.03) / 2)),
                Part("cylinder", (0.25, 0.02), (0.5, 0.5, 0.5), (0, 0, 0.01))], h
    if kind == "chair":
        seat = 0.45
        return [Part("box", (d, w, 0.05), c, (0, 0, seat - 0.025)),
                Part("box", (0.05, w, h - seat), c, (-d / 2 + 0.025, 0, (seat + h) / 2)),
                *_legs(d, w, seat - 0.05, dark, 0.02)], seat
    if kind in ("armchair", "sofa"):
        return _upholstered(d, w, h, c, 0.45 if kind == "armchair" else 0.42)
    if kind == "bed":
        return [Part("box", (d, w, 0.3), c, (0, 0, 0.15)),
                Part("box", (d - 0.05, w - 0.05, h - 0.3), (0.95, 0.95, 0.92),
                     (0, 0, (h + 0.3) / 2)),
                Part("box", (0.35, w - 0.3, 0.1), (1, 1, 1), (-d / 2 + 0.3, 0, h + 0.05)),
                Part("box", (0.06, w, 1.0), dark, (-d / 2 - 0.03, 0, 0.5))], h
    if kind == "shelf":
        boards = [Part("box", (d, w, 0.03), c, (0, 0, z * (h - 0.03) / 4 + 0.015))
                  for z in range(5)]
        sides = [Part("box", (d, 0.03, h), c, (0, s * (w / 2 - 0.015), h / 2)) for s in (1, -1)]
        return [*boards, *sides, Part("box", (0.01, w, h), dark, (-d / 2 + 0.005, 0, h / 2))], h
    if kind == "tv":
        cabinet = 0.5
        return [Part("box", (d, w, cabinet), c, (0, 0, cabinet / 2)),
                Part("box", (0.05, 0.1, 0.08), DARK, (0, 0, cabinet + 0.04)),
                Part("box", (0.05, 0.9 * w, h - cabinet - 0.08), DARK,
                     (0, 0, (h + cabinet + 0.08) / 2)),
                Part("box", (0.005, 0.86 * w, h - cabinet - 0.12), (0.12, 0.16, 0.22),
                     (0.027, 0, (h + cabinet + 0.08) / 2), collide=False)], cabinet
    if kind == "plant":
        pot = 0.35
        return [Part("cylinder", (d / 2 * 0.7, pot), c, (0, 0, pot / 2)),
                Part("cylinder", (0.02, h - w / 2 - pot), (0.35, 0.25, 0.1),
                     (0, 0, pot + (h - w / 2 - pot) / 2)),
                Part("sphere", (w / 2,), (0.2, 0.55, 0.2), (0, 0, h - w / 2))], pot
    raise ValueError(f"unknown furniture type {kind!r}")


# pybullet_data models: file, scale for a realistic size, roll to stand it upright.
URDF_OBJECTS: dict[str, tuple[str, float, float]] = {
    "duck": ("duck_vhacd.urdf", 2.0, math.pi / 2),
    "teddy": ("teddy_vhacd.urdf", 3.0, math.pi / 2),
    "tray": ("tray/traybox.urdf", 0.6, 0.0),
    "sphere": ("sphere2red.urdf", 0.2, 0.0),
}
OBJECT_COLOURS = {"mug": "#d9d4c7", "cake": "#f5d7b0", "ball": "#d23c3c", "book": "#2f6f4f",
                  "plate": "#f7f7f7"}


def object_xml(o: SceneObject, c: Rgb) -> str:
    """URDF text of a primitive object (origin at its bottom centre), before scaling."""
    k = o.scale

    def part(shape: str, size: tuple[float, ...], colour: Rgb, xyz: tuple[float, float, float],
             collide: bool = True) -> Part:
        return Part(shape, tuple(v * k for v in size), colour,  # type: ignore[arg-type]
                    (xyz[0] * k, xyz[1] * k, xyz[2] * k), collide=collide)

    if o.type == "mug":
        parts = [part("cylinder", (0.04, 0.1), c, (0, 0, 0.05)),
                 part("box", (0.03, 0.012, 0.06), c, (0.05, 0, 0.05))]
    elif o.type == "ball":
        parts = [part("sphere", (0.11,), c, (0, 0, 0.11))]
    elif o.type == "book":
        parts = [part("box", (0.22, 0.16, 0.04), c, (0, 0, 0.02))]
    elif o.type == "plate":
        parts = [part("cylinder", (0.12, 0.015), c, (0, 0, 0.0075))]
    else:  # cake: two layers with icing, candles as their own links (with flames when lit)
        icing = (0.95, 0.6, 0.75)
        parts = [part("cylinder", (0.15, 0.08), c, (0, 0, 0.04)),
                 part("cylinder", (0.155, 0.01), icing, (0, 0, 0.085)),
                 part("cylinder", (0.1, 0.06), c, (0, 0, 0.12)),
                 part("cylinder", (0.103, 0.008), icing, (0, 0, 0.154))]
        xml, colours = link_xml("base", parts), ((0.3, 0.5, 0.95), (0.95, 0.9, 0.3))
        for i in range(o.candles):
            a = 2 * math.pi * i / o.candles
            r = 0.0 if o.candles == 1 else 0.07
            flame = [part("sphere", (0.009,), (1.0, 0.7, 0.1), (0, 0, 0.07), False)]
            flame = flame if o.lit else []
            candle = [part("cylinder", (0.006, 0.06), colours[i % 2], (0, 0, 0.03)), *flame]
            xml += link_xml(f"candle_{i}", candle)
            xml += joint_xml(f"candle_{i}_joint", "base", f"candle_{i}",
                             (r * math.cos(a) * k, r * math.sin(a) * k, 0.158 * k))
        return xml
    return link_xml("base", parts)
