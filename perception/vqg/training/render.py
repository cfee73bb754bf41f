"""Build a :class:`perception.vqg.training.layout.Plan` in PyBullet, render the head camera,
and keep in the scene graph only what the frame shows.

The room, light and furniture come from :mod:`perception.detector.training.data` and
:func:`sim.furnishings.furniture_parts`; mugs, plates, books, balls and the cake with its
candles from :mod:`sim.furnishings`'s primitive objects; the duck, teddy and tray from
``pybullet_data``.

Visibility rule: a node is kept when at least ``min_pixels[category]`` pixels of the
segmentation mask belong to it (candles are the cake's own links and are counted one by one);
relations to a dropped node are dropped with it (its ``support`` becomes empty, ``near``
lists only kept furniture).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pybullet as p
import pybullet_data

from perception.detector.config import ImageConfig, load_detector_config
from perception.detector.training.data import DetectorScene, room_parts
from perception.vqg.scene import PALETTE, Node, SceneGraph
from perception.vqg.training.data_config import VisibilityConfig
from perception.vqg.training.layout import Plan
from sim.furnishings import URDF_OBJECTS, furniture_parts, object_xml
from sim.layout import SceneObject
from sim.people import Part, Person, build_body, load_urdf_text

CANDLE_COLOURS = ("blue", "yellow")  # sim.world paints candles blue and yellow in turn
PRIMITIVES = ("mug", "plate", "book", "ball", "cake")
TEXTURED = ("duck", "tray")  # keep their pybullet_data textures (yellow, grey)


def _extra_parts(node: Node) -> list[Part]:
    """Parts of the objects sim.world does not build: balloon, present, block."""
    c, k = PALETTE[node.colour], node.size[0] if node.size else 1.0
    if node.kind == "balloon":
        return [Part("sphere", (0.13,), c), Part("cylinder", (0.004, 0.9), (0.9, 0.9, 0.9),
                                                  (0, 0, -0.58), collide=False)]
    if node.kind == "present":
        ribbon = PALETTE["white" if node.colour != "white" else "red"]
        s = 0.3 * k
        return [Part("box", (s, s, 0.8 * s), c, (0, 0, 0.4 * s)),
                Part("box", (s + 0.01, 0.15 * s, 0.8 * s + 0.01), ribbon, (0, 0, 0.4 * s)),
                Part("box", (0.15 * s, s + 0.01, 0.8 * s + 0.01), ribbon, (0, 0, 0.4 * s))]
    return [Part("box", (0.1 * k, 0.1 * k, 0.1 * k), c, (0, 0, 0.05 * k))]


class VqgRenderer(DetectorScene):
    """A PyBullet DIRECT client with the robot (the detector's renderer) for VQG scenes."""

    def __init__(self, width: int, height: int, visibility: VisibilityConfig) -> None:
        data = load_detector_config().data
        super().__init__(data.model_copy(update={"image": ImageConfig(width=width, height=height)}))
        self.visibility = visibility
        #: body ids, link indices and node id -> body id of the last render (for checks)
        self.last_mask: tuple[np.ndarray, np.ndarray, dict[str, int]] | None = None

    def _object(self, node: Node) -> int:
        c, pos = self.client, (node.x, node.y, node.z)
        scale = node.size[0] if node.size else 1.0
        if node.kind in PRIMITIVES:
            spec = SceneObject(type=node.kind, x=0, y=0, scale=scale, candles=node.candles,  # type: ignore[arg-type]
                               lit=node.lit)
            return load_urdf_text(c, node.id, object_xml(spec, PALETTE[node.colour]), pos,
                                  node.yaw)
        if node.kind not in URDF_OBJECTS:
            return build_body(c, node.id, _extra_parts(node), pos, node.yaw)
        file, k, roll = URDF_OBJECTS[node.kind]
        body = p.loadURDF(str(Path(pybullet_data.getDataPath()) / file), (0, 0, 0),
                          p.getQuaternionFromEuler((roll, 0, node.yaw)), useFixedBase=True,
                          globalScaling=k * scale, physicsClientId=c)
        if node.kind not in TEXTURED:
            p.changeVisualShape(body, -1, rgbaColor=(*PALETTE[node.colour], 1), physicsClientId=c)
        (x0, y0, z0), (x1, y1, _) = p.getAABB(body, -1, physicsClientId=c)
        p.resetBasePositionAndOrientation(
            body, (node.x - (x0 + x1) / 2, node.y - (y0 + y1) / 2, node.z - z0),
            p.getQuaternionFromEuler((roll, 0, node.yaw)), physicsClientId=c)
        return body

    def render_plan(self, plan: Plan) -> tuple[np.ndarray, SceneGraph]:
        """Render ``plan`` and return the RGB frame and the graph of what it shows."""
        built = [build_body(self.client, "room", room_parts(plan.room))]
        people: list[Person] = []
        ids: dict[str, int] = {}
        try:
            for n in plan.graph.nodes:
                if n.category == "furniture":
                    parts, _ = furniture_parts(n.kind, *n.size, PALETTE[n.colour])
                    ids[n.id] = build_body(self.client, n.id, parts, (n.x, n.y, 0), n.yaw)
                elif n.category == "person":
                    people.append(Person(self.client, plan.looks[n.id], n.x, n.y, n.yaw,
                                         n.pose, n.id))  # type: ignore[arg-type]
                    ids[n.id] = people[-1].body_id
                else:
                    ids[n.id] = self._object(n)
                built.append(ids[n.id])
            self.robot.camera.set_lighting(plan.room.light.camera_kwargs())
            p.resetJointState(self.robot.body_id, self._head_pitch, plan.room.head_pitch,
                              physicsClientId=self.client)
            rgb, bodies, links = self._render()
            self.last_mask = (bodies, links, ids)
        finally:
            for body in built:
                p.removeBody(body, physicsClientId=self.client)
        return rgb, visible_graph(plan.graph, ids, bodies, links, self.visibility)


def visible_graph(graph: SceneGraph, ids: dict[str, int], bodies: np.ndarray,
                  links: np.ndarray, vis: VisibilityConfig) -> SceneGraph:
    """``graph`` with the visibility rule applied to the segmentation ``bodies``/``links``
    (``ids``: node id -> body id), and image sides, distances and the near set filled in."""
    width = bodies.shape[1]
    cols = np.broadcast_to(np.arange(width), bodies.shape)
    kept: list[Node] = []
    for n in graph.nodes:
        mask = bodies == ids[n.id]
        if n.kind == "cake":
            parts = [mask & (links == i) for i in range(n.candles)]
            n.candles = sum(int(m.sum()) >= vis.min_pixels.candle for m in parts)
            for i, m in enumerate(parts):
                if int(m.sum()) >= vis.min_pixels.candle:
                    kept.append(Node(f"candle_{sum(k.kind == 'candle' for k in kept)}",
                                     "candle", CANDLE_COLOURS[i % 2], n.x, n.y, n.z,
                                     support=n.id, pixels=int(m.sum()), lit=n.lit,
                                     side=_side(cols[m], width)))
            mask = mask & (links < 0)
        n.pixels = int(mask.sum())
        if n.pixels >= getattr(vis.min_pixels, n.category):
            n.side, n.distance = _side(cols[mask], width), round(math.hypot(n.x, n.y), 3)
            kept.append(n)
    keep = {n.id for n in kept}
    if not any(n.kind == "cake" for n in kept):  # no candles without their cake
        kept = [n for n in kept if n.kind != "candle"]
    furniture = [f for f in kept if f.category == "furniture"]
    for n in kept:
        if n.support not in keep and n.support != "floor":
            n.support = ""
        if n.kind == "candle" or (n.category == "object" and n.support not in ("floor", "")):
            continue
        n.near = [f.id for f in furniture if f.id not in (n.id, n.support)
                  and math.hypot(f.x - n.x, f.y - n.y) < vis.near_m + max(f.size[:2]) / 2]
    return SceneGraph(graph.room, graph.occasion, kept, graph.width, graph.height)


def _side(cols: np.ndarray, width: int) -> str:
    """Which third of the image a mask's centroid column is in."""
    c = float(cols.mean()) / width
    return "left" if c < 1 / 3 else "right" if c > 2 / 3 else "middle"
