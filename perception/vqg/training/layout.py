"""Seeded household layouts for the VQG renders: room, occasion, furniture, objects, people.

:func:`sample_plan` draws one :class:`Plan` from a seed. The robot stands at the origin facing
+x; every scene has a main surface (coffee table, table or cake table) in front of the robot,
the room's typical furniture, people placed by what they do (eaters on chairs round the
table, sitters on seats, celebrators behind the cake, dancers on free floor, talkers facing
each other, readers holding a book) and small objects on the surfaces, on the floor and, for
parties, balloons in the air. The graph of a plan lists everything built; the renderer drops
what the camera does not see.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from perception.detector.training.data import FURNITURE_SIZES, SKINS, SceneSpec
from perception.vqg.scene import (
    ACTIVITY_MIX,
    MAIN_SURFACE,
    PALETTE,
    ROOM_FURNITURE,
    ROOM_OCCASIONS,
    ROOMS,
    SEATS,
    SURFACE_MIX,
    TOYS,
    Node,
    SceneGraph,
)
from perception.vqg.training.data_config import SceneConfig
from sim.lighting import Light
from sim.people import Appearance

FIXED_COLOUR = {"duck": "yellow", "cake": "white", "plate": "white", "tray": "grey"}
OBJECT_SCALE = {"ball": 0.6, "block": 1.0, "duck": 1.0, "teddy": 1.0}  # on a surface


@dataclass
class Plan:
    """One scene before rendering: its graph, how each person looks, and the room."""

    graph: SceneGraph
    looks: dict[str, Appearance]
    room: SceneSpec


class _Drawer:
    """Keeps the rng, node ids and the occupied floor while a plan is drawn."""

    def __init__(self, rng: np.random.Generator, cfg: SceneConfig, hfov: float) -> None:
        self.rng, self.cfg, self.tan = rng, cfg, math.tan(hfov / 2)
        self.nodes: list[Node] = []
        self.looks: dict[str, Appearance] = {}
        self.floor: list[tuple[float, float, float]] = []  # occupied discs x, y, r
        self.tops: dict[str, list[tuple[float, float]]] = {}  # items on each surface

    def u(self, lo: float, hi: float) -> float:
        return float(self.rng.uniform(lo, hi))

    def pick(self, options: dict[str, float] | tuple[str, ...]) -> str:
        keys = list(options)
        w = np.array([options[k] for k in keys] if isinstance(options, dict) else [1.0] * len(keys))
        return keys[int(self.rng.choice(len(keys), p=w / w.sum()))]

    def colour(self, avoid: str = "") -> str:
        return self.pick(tuple(c for c in PALETTE if c != avoid))

    def add(self, kind: str, **kw: object) -> Node:
        i = sum(n.kind == kind for n in self.nodes)
        node = Node(f"{kind}_{i}", kind, **kw)  # type: ignore[arg-type]
        self.nodes.append(node)
        return node

    def free(self, x: float, y: float, r: float) -> bool:
        return all(math.hypot(x - a, y - b) > r + c for a, b, c in self.floor)

    def spot(self, r: float, xs: tuple[float, float],
             margin: float = 0.9) -> tuple[float, float] | None:
        """A free floor position in view, at depth ``xs``."""
        for _ in range(30):
            x = self.u(*xs)
            y = self.u(-1, 1) * max(x * self.tan * margin - r, 0.05)
            if self.free(x, y, r):
                return x, y
        return None

    def furniture(self, kind: str, x: float, y: float, yaw: float) -> Node:
        j = self.cfg.size_jitter
        size = tuple(v * self.u(1 - j, 1 + j) for v in FURNITURE_SIZES[kind])
        self.floor.append((x, y, 0.45 * max(size[:2])))
        return self.add(kind, colour=self.colour(), x=x, y=y, yaw=yaw, size=size)

    def person(self, activity: str, x: float, y: float, yaw: float, pose: str,
               support: str = "") -> Node:
        cfg = self.cfg
        height = self.u(*cfg.person_height)
        shirt = self.colour()
        trousers = self.colour(shirt)
        node = self.add("person", colour=shirt, trousers=trousers, x=x, y=y, yaw=yaw, pose=pose,
                        activity=activity, support=support, size=(height,))
        self.looks[node.id] = Appearance(
            height, height * self.u(0.22, 0.3), PALETTE[shirt], PALETTE[trousers],
            SKINS[int(self.rng.integers(len(SKINS)))],
            tuple(float(v) for v in self.rng.uniform(0.02, 0.4, 3)))  # type: ignore[arg-type]
        self.floor.append((x, y, 0.3))
        return node

    def on(self, base: Node, kind: str, spacing: float, at: tuple[float, float] | None = None,
           **kw: object) -> Node | None:
        """Put an object on ``base``'s top (near local ``at`` when given)."""
        d, w, h = base.size
        placed = self.tops.setdefault(base.id, [])
        for _ in range(20):
            lu, lv = at if at is not None else (self.u(-0.38, 0.38) * d, self.u(-0.38, 0.38) * w)
            if all(math.hypot(lu - a, lv - b) > spacing for a, b in placed):
                placed.append((lu, lv))
                c, s = math.cos(base.yaw), math.sin(base.yaw)
                kw.setdefault("colour", FIXED_COLOUR.get(kind) or self.colour())
                return self.add(kind, x=base.x + c * lu - s * lv, y=base.y + s * lu + c * lv,
                                z=h, yaw=self.u(-math.pi, math.pi), support=base.id, **kw)
            at = None
        return None


def _seat_person(dr: _Drawer, activity: str, seats: list[Node]) -> Node | None:
    """A sitter on an existing sofa with room left, or on a new armchair or chair."""
    sofa = next((s for s in seats if s.kind == "sofa" and len(dr.tops.get(s.id, [])) < 2), None)
    if sofa is not None:
        slots = dr.tops.setdefault(sofa.id, [])
        v = (0.25, -0.25)[len(slots)] * sofa.size[1]
        slots.append((0.1, v))
        c, s = math.cos(sofa.yaw), math.sin(sofa.yaw)
        return dr.person(activity, sofa.x + 0.1 * c - s * v, sofa.y + 0.1 * s + c * v, sofa.yaw,
                         "sitting", sofa.id)
    where = dr.spot(0.5, (2.5, 5.0))
    if where is None:
        return None
    yaw = math.atan2(-where[1], -where[0]) + dr.u(-0.6, 0.6)
    seat = dr.furniture(dr.pick(("armchair", "chair")), where[0], where[1], yaw)
    seats.append(seat)
    c, s = math.cos(yaw), math.sin(yaw)
    return dr.person(activity, seat.x + 0.1 * c, seat.y + 0.1 * s, yaw, "sitting", seat.id)


def _eater(dr: _Drawer, table: Node, k: int) -> Node | None:
    """The k-th eater on a chair at the far or a long side of the table, with a plate."""
    d, w, _ = table.size
    side = ((d / 2 + 0.3, 0.0, math.pi), (0.0, w / 2 + 0.3, -math.pi / 2),
            (0.0, -w / 2 - 0.3, math.pi / 2))[k % 3]
    c, s = math.cos(table.yaw), math.sin(table.yaw)
    x, y = table.x + c * side[0] - s * side[1], table.y + s * side[0] + c * side[1]
    if k >= 3 or not dr.free(x, y, 0.25):
        return None
    yaw = table.yaw + side[2]
    chair = dr.furniture("chair", x - 0.1 * math.cos(yaw), y - 0.1 * math.sin(yaw), yaw)
    person = dr.person("eating", x, y, yaw, "sitting", chair.id)
    dr.on(table, "plate", 0.22, (0.6 * side[0], 0.6 * side[1]))
    return person


def _place_people(dr: _Drawer, occasion: str, table: Node, seats: list[Node]) -> None:
    n = int(dr.rng.integers(dr.cfg.people[0], dr.cfg.people[1] + 1))
    eaters = 0
    for _ in range(n):
        act = dr.pick(ACTIVITY_MIX[occasion])
        if act == "eating":
            eaters += _eater(dr, table, eaters) is not None
            continue
        if act in ("sitting", "watching_tv") or (act == "reading" and dr.rng.random() < 0.7):
            if act == "watching_tv" and not any(q.kind == "tv" for q in dr.nodes):
                spot = dr.spot(0.6, (3.5, 5.5))
                if spot is not None:
                    dr.furniture("tv", *spot, math.atan2(-spot[1], -spot[0]) + dr.u(-0.8, 0.8))
            person = _seat_person(dr, act, seats)
        else:
            spot = dr.spot(0.35, (2.6, 5.2) if act != "celebrating" else
                           (table.x + 0.5, table.x + 1.2))
            if spot is None:
                continue
            face = math.atan2(-spot[1], -spot[0])
            pose = "arms_raised" if act in ("celebrating", "dancing") and dr.rng.random() < 0.6 \
                else "standing"
            yaw = dr.u(-math.pi, math.pi) if act == "dancing" else face + dr.u(-0.5, 0.5)
            person = dr.person(act, *spot, yaw, pose)
        if person is not None and act == "reading":
            c, s = math.cos(person.yaw), math.sin(person.yaw)
            lift = 0.65 if person.pose == "sitting" else 0.62 * person.size[0]
            dr.add("book", colour=dr.colour(), x=person.x + 0.3 * c, y=person.y + 0.3 * s,
                   z=lift, yaw=person.yaw)
    talkers = [q for q in dr.nodes if q.kind == "person" and q.activity == "talking"]
    for q in talkers:  # face the nearest other person
        others = [o for o in dr.nodes if o.kind == "person" and o is not q]
        if others:
            o = min(others, key=lambda o: math.hypot(o.x - q.x, o.y - q.y))
            q.yaw = math.atan2(o.y - q.y, o.x - q.x)


def _place_objects(dr: _Drawer, occasion: str, table: Node) -> None:
    cfg = dr.cfg
    if occasion == "birthday_party":
        lo, hi = cfg.candles
        dr.on(table, "cake", 0.35, (0.0, 0.0), colour=dr.pick(("white", "pink", "brown")),
              candles=int(dr.rng.integers(lo, hi + 1)),
              lit=bool(dr.rng.random() < cfg.lit_fraction))
    surfaces = [table, *(n for n in dr.nodes
                         if n.kind in ("coffee_table", "shelf") and n is not table)]
    for _ in range(int(dr.rng.integers(cfg.surface_objects[0], cfg.surface_objects[1] + 1))):
        kind = dr.pick(SURFACE_MIX[occasion])
        dr.on(surfaces[int(dr.rng.integers(len(surfaces)))] if dr.rng.random() < 0.3 else table,
              kind, 0.2, size=(OBJECT_SCALE.get(kind, 1.0),))
    lo, hi = cfg.floor_objects
    extra = 2 if occasion == "playtime" else 0
    for _ in range(int(dr.rng.integers(lo, hi + 1)) + extra):
        kind = dr.pick((*TOYS, "present") if occasion == "birthday_party" else TOYS)
        spot = dr.spot(0.15, (2.3, 4.2))
        if spot is not None:
            dr.floor.append((*spot, 0.15))
            dr.add(kind, colour=FIXED_COLOUR.get(kind) or dr.colour(), x=spot[0], y=spot[1],
                   yaw=dr.u(-math.pi, math.pi), support="floor", size=(1.0,))
    if occasion in ("birthday_party", "dance_party"):
        for _ in range(int(dr.rng.integers(cfg.balloons[0], cfg.balloons[1] + 1))):
            x = dr.u(2.5, 5.0)
            dr.add("balloon", colour=dr.colour(), x=x, y=dr.u(-1, 1) * x * dr.tan * 0.8,
                   z=dr.u(1.3, 1.9))


def sample_plan(seed: int | np.random.SeedSequence, cfg: SceneConfig, hfov: float) -> Plan:
    """Draw one scene for a camera of horizontal field of view ``hfov`` (rad)."""
    dr = _Drawer(np.random.default_rng(seed), cfg, hfov)
    room = dr.pick(ROOMS)
    occasion = dr.pick(ROOM_OCCASIONS[room])
    kind = "cake_table" if room == "party_room" and occasion == "birthday_party" \
        else MAIN_SURFACE[room]
    table = dr.furniture(kind, dr.u(*cfg.table_distance), dr.u(-0.4, 0.4),
                         0.0 if dr.rng.random() < 0.5 else math.pi / 2)
    seats: list[Node] = []
    if room == "living_room":
        seats.append(dr.furniture("sofa", table.x + dr.u(1.0, 1.4), table.y + dr.u(-0.3, 0.3),
                                  math.pi))
    for _ in range(int(dr.rng.integers(cfg.extra_furniture[0], cfg.extra_furniture[1] + 1))):
        extra = dr.pick(ROOM_FURNITURE[room])
        spot = dr.spot(0.6, (2.8, 6.0), margin=1.1)
        if spot is not None:
            seats.append(dr.furniture(extra, *spot, math.atan2(-spot[1], -spot[0])
                                      + dr.u(-0.5, 0.5)))
    _place_people(dr, occasion, table, [s for s in seats if s.kind in SEATS])
    _place_objects(dr, occasion, table)
    xs = [abs(n.x) for n in dr.nodes] + [0.0]
    ys = [abs(n.y) for n in dr.nodes] + [0.0]
    light = Light((dr.u(-1, 1), dr.u(-1, 1), dr.u(0.3, 1.5)),
                  tuple(float(v) for v in dr.rng.uniform(0.85, 1.0, 3)),  # type: ignore[arg-type]
                  dr.u(*cfg.ambient), dr.u(*cfg.diffuse), dr.u(*cfg.specular),
                  bool(dr.rng.random() < cfg.shadow_fraction))
    spec = SceneSpec((), (), max(dr.u(*cfg.depth), max(xs) + 1.2),
                     max(dr.u(*cfg.half_width), max(ys) + 1.0),
                     tuple(float(v) for v in dr.rng.uniform(0.45, 0.95, 3)),  # type: ignore[arg-type]
                     tuple(float(v) for v in dr.rng.uniform(0.25, 0.7, 3)),  # type: ignore[arg-type]
                     light, dr.u(*cfg.head_pitch))
    return Plan(SceneGraph(room, occasion, dr.nodes, cfg.width, cfg.height), dr.looks, spec)
