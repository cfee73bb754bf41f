"""The static household of a scenario in PyBullet: the floor, the walls of each room with
their door gaps, ceilings, furniture and objects (from primitives or ``pybullet_data``
models) and the charging dock. Once built it is the robot's map of its home
(:class:`robot.navigation.FloorPlan`): rooms, the footprints and heights of what does not
move, and the dock; the people are the world's (sim/world.py)."""

from __future__ import annotations

import math
from pathlib import Path

import pybullet as p
import pybullet_data

from robot.geometry import Footprint, Pose2D
from sim.furnishings import (
    DARK,
    FURNITURE_COLOURS,
    OBJECT_COLOURS,
    URDF_OBJECTS,
    furniture_parts,
    object_xml,
)
from sim.layout import Furniture, Placement, SceneObject, rgb
from sim.people import Part, Rgb, build_body, joint_xml, link_xml, load_urdf_text
from sim.scenario import Scenario

WALL_THICKNESS = 0.1
DOOR_HEIGHT = 2.05
CEILING: Rgb = (0.96, 0.96, 0.94)


Span = tuple[float, float]


def _subtract(span: Span, cuts: list[Span]) -> list[Span]:
    """The parts of ``span`` not covered by any of ``cuts`` (1-D intervals)."""
    pieces = [span]
    for c0, c1 in cuts:
        pieces = [q for a, b in pieces for q in ((a, min(b, c0)), (max(a, c1), b))
                  if q[1] - q[0] > 1e-6]
    return pieces


def door_line(x: tuple[float, float], y: tuple[float, float], wall: str,
              offset: float) -> tuple[tuple[str, float], float]:
    """The wall line key of a door and its centre coordinate along that line."""
    if wall in ("south", "north"):
        return ("h", round(y[0] if wall == "south" else y[1], 3)), x[0] + offset
    return ("v", round(x[0] if wall == "west" else x[1], 3)), y[0] + offset


def pose_of(place: Placement) -> Pose2D:
    """A scenario placement as a pose (its yaw from degrees to radians)."""
    return Pose2D(place.x, place.y, math.radians(place.yaw))


class House:
    """The static scene of ``scenario`` built into ``client``; the bodies it makes go into
    ``bodies`` by name."""

    def __init__(self, scenario: Scenario, client: int, bodies: dict[str, int]) -> None:
        self.scenario, self.client, self.bodies = scenario, client, bodies
        self.footprints: list[Footprint] = []
        self._tops: dict[str, float] = {}
        self._build_house()
        for f in scenario.furniture:
            self._build_furniture(f)
        for i, o in enumerate(scenario.objects):
            self._build_object(o, o.name or f"{o.type}_{i}")
        self._build_dock()

    def _build_house(self) -> None:
        rooms = self.scenario.rooms
        floors = [Part("box", (r.x[1] - r.x[0], r.y[1] - r.y[0], 0.01), rgb(r.floor_colour),
                       ((r.x[0] + r.x[1]) / 2, (r.y[0] + r.y[1]) / 2, -0.005), collide=False)
                  for r in rooms]
        walls: list[Part] = []
        built: dict[tuple[str, float], list[tuple[float, float]]] = {}
        doors: dict[tuple[str, float], list[tuple[float, float]]] = {}
        for r in rooms:
            for d in r.doors:
                key, c = door_line(r.x, r.y, d.wall, d.offset)
                doors.setdefault(key, []).append((c - d.width / 2, c + d.width / 2))
        t = WALL_THICKNESS
        for r in rooms:
            colour, h = rgb(r.wall_colour), r.wall_height
            sides = [(("h", r.y[0]), r.x), (("h", r.y[1]), r.x), (("v", r.x[0]), r.y),
                     (("v", r.x[1]), r.y)]
            for (axis, at), (a, b) in sides:
                key = (axis, round(at, 3))
                gaps = doors.get(key, [])
                for a0, b0 in _subtract((a - t / 2, b + t / 2), gaps + built.get(key, [])):
                    walls.append(self._wall_part(axis, at, a0, b0, 0.0, h, colour))
                for g0, g1 in gaps:
                    if h > DOOR_HEIGHT + 0.05 and a < (g0 + g1) / 2 < b:
                        walls.append(self._wall_part(axis, at, g0, g1, DOOR_HEIGHT, h, colour))
                built.setdefault(key, []).append((a - t / 2, b + t / 2))
        ceilings = [Part("box", (r.x[1] - r.x[0], r.y[1] - r.y[0], 0.02), CEILING,
                         ((r.x[0] + r.x[1]) / 2, (r.y[0] + r.y[1]) / 2, r.wall_height + 0.01),
                         collide=False) for r in rooms if r.ceiling]
        xml = link_xml("floor", floors) + link_xml("walls", walls) + link_xml("ceiling", ceilings)
        xml += joint_xml("walls_joint", "floor", "walls", (0, 0, 0))
        xml += joint_xml("ceiling_joint", "floor", "ceiling", (0, 0, 0))
        self.bodies["house"] = load_urdf_text(self.client, "house", xml)

    def _wall_part(self, axis: str, at: float, a: float, b: float, z0: float, z1: float,
                   colour: Rgb) -> Part:
        mid, length, t = (a + b) / 2, b - a, WALL_THICKNESS
        if z0 == 0.0:
            self.footprints.append(Footprint(
                "wall", "wall", mid if axis == "h" else at, at if axis == "h" else mid,
                0.0, (length if axis == "h" else t) / 2, (t if axis == "h" else length) / 2))
        size = (length, t, z1 - z0) if axis == "h" else (t, length, z1 - z0)
        xyz = (mid, at, (z0 + z1) / 2) if axis == "h" else (at, mid, (z0 + z1) / 2)
        return Part("box", size, colour, xyz)

    def _build_furniture(self, f: Furniture) -> None:
        d, w, h = f.dims
        parts, top = furniture_parts(f.type, d, w, h, rgb(f.colour or FURNITURE_COLOURS[f.type]))
        yaw = math.radians(f.yaw)
        self.bodies[f.name] = build_body(self.client, f.name, parts, (f.x, f.y, 0), yaw)
        self._tops[f.name] = top
        self.footprints.append(Footprint(f.name, "furniture", f.x, f.y, yaw, d / 2, w / 2))

    def _build_object(self, o: SceneObject, name: str) -> None:
        x, y, z = o.x, o.y, 0.0
        if o.on_top_of is not None:
            base = next(f for f in self.scenario.furniture if f.name == o.on_top_of)
            x, y = (base.x if x is None else x), (base.y if y is None else y)
            z = self._tops[o.on_top_of]
        assert x is not None and y is not None  # guaranteed by the scenario checks
        yaw = math.radians(o.yaw)
        if o.type in URDF_OBJECTS:
            file, scale, roll = URDF_OBJECTS[o.type]
            body = p.loadURDF(str(Path(pybullet_data.getDataPath()) / file), (0, 0, 0),
                              p.getQuaternionFromEuler((roll, 0, yaw)), useFixedBase=True,
                              globalScaling=scale * o.scale, physicsClientId=self.client)
            if o.colour is not None:
                p.changeVisualShape(body, -1, rgbaColor=(*rgb(o.colour), 1),
                                    physicsClientId=self.client)
        else:
            colour = rgb(o.colour or OBJECT_COLOURS[o.type])
            body = load_urdf_text(self.client, name, object_xml(o, colour), (0, 0, 0), yaw)
        (x0, y0, z0), (x1, y1, _) = p.getAABB(body, -1, physicsClientId=self.client)
        pos, orn = p.getBasePositionAndOrientation(body, physicsClientId=self.client)
        p.resetBasePositionAndOrientation(
            body, (x + pos[0] - (x0 + x1) / 2, y + pos[1] - (y0 + y1) / 2, z + pos[2] - z0),
            orn, physicsClientId=self.client)
        self.bodies[name] = body
        if o.on_top_of is None:
            self.footprints.append(Footprint(name, "object", x, y, 0.0, (x1 - x0) / 2,
                                              (y1 - y0) / 2))

    def _build_dock(self) -> None:
        """A dark pad with yellow edges and a back plate carrying a cyan-cross marker.

        The dock pose is where the robot stands when docked, facing the plate (+x locally).
        """
        yellow, white, cyan = (0.95, 0.8, 0.1), (0.95, 0.95, 0.95), (0.0, 0.85, 0.9)
        plate_x = 0.38
        parts = [Part("box", (0.7, 0.6, 0.02), (0.2, 0.2, 0.22), (0, 0, 0.01), collide=False),
                 *[Part("box", (0.7, 0.05, 0.024), yellow, (0, s * 0.3, 0.012), collide=False)
                   for s in (1, -1)],
                 Part("box", (0.04, 0.5, 0.45), white, (plate_x, 0, 0.245)),
                 Part("box", (0.006, 0.32, 0.32), DARK, (plate_x - 0.023, 0, 0.27), collide=False),
                 Part("box", (0.006, 0.24, 0.06), cyan, (plate_x - 0.027, 0, 0.27), collide=False),
                 Part("box", (0.006, 0.06, 0.24), cyan, (plate_x - 0.027, 0, 0.27), collide=False)]
        dock = self.dock_pose()
        self.bodies["dock"] = build_body(self.client, "dock", parts, (dock.x, dock.y, 0), dock.yaw)
        c, s = math.cos(dock.yaw), math.sin(dock.yaw)
        self.footprints.append(Footprint("dock", "dock", dock.x + c * plate_x,
                                          dock.y + s * plate_x, dock.yaw, 0.02, 0.25))

    def dock_pose(self) -> Pose2D:
        """Where the robot stands when docked, facing the dock's marker plate."""
        return pose_of(self.scenario.dock)

    def furniture_top(self, name: str) -> float:
        """Height (m) of the top of the furniture item ``name`` (KeyError: no such item)."""
        return self._tops[name]

    def room_at(self, x: float, y: float) -> str | None:
        """The name of the room holding ``(x, y)``, or None (a wall, outside)."""
        return next((r.name for r in self.scenario.rooms if r.contains(x, y, 0.0)), None)

    def room_bounds(self) -> dict[str, tuple[float, float, float, float]]:
        """``(x_min, y_min, x_max, y_max)`` of each room, by name."""
        return {r.name: (r.x[0], r.y[0], r.x[1], r.y[1]) for r in self.scenario.rooms}

    def obstacles(self) -> list[Footprint]:
        """Floor footprints of walls, furniture, floor objects and the dock plate."""
        return list(self.footprints)
