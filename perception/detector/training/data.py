"""Labelled frames for the person-and-face detector, rendered from the robot's head camera.

Each frame is one randomised room (wall and floor colours, TinyRenderer light), a few
furniture items built with :func:`sim.furnishings.furniture_parts`, and 0-4 people from
:mod:`sim.people`, seen by a :class:`sim.robot.Robot` standing at the origin facing +x.
Boxes come from the segmentation mask; docs/detector.md gives the rule for tiny and
occluded instances. :func:`write_dataset` writes an ultralytics YOLO data set.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

import cv2
import numpy as np
import pybullet as p
import yaml

from core.checkpoint import atomic_write_bytes
from perception.detector.config import DataConfig
from sim.furnishings import furniture_parts
from sim.head_camera import decode_segmentation
from sim.house import WALL_THICKNESS
from sim.lighting import Light
from sim.people import POSES, Appearance, Part, Person, PoseName, build_body
from sim.robot import Robot

Rgb = tuple[float, float, float]
CLASSES = ("person", "face")
SPLITS = ("train", "val", "test")
VIEWS = ("front", "side", "back")
FAR = 1000.0  # bodies are parked this far below the floor to render one person alone
# Base size (depth, width, height in m) of each furniture kind; each draw scales it by +-15 %.
FURNITURE_SIZES: dict[str, tuple[float, float, float]] = {
    "table": (1.1, 0.8, 0.75), "coffee_table": (0.6, 1.0, 0.45), "chair": (0.45, 0.45, 0.9),
    "armchair": (0.8, 0.85, 0.9), "sofa": (0.9, 2.0, 0.85), "shelf": (0.35, 1.0, 1.6),
    "plant": (0.4, 0.5, 1.2), "tv": (0.45, 1.2, 1.2), "bed": (2.0, 1.5, 0.55),
    "cake_table": (0.7, 0.7, 0.75),
}
SKINS: tuple[Rgb, ...] = ((0.96, 0.8, 0.69), (0.87, 0.69, 0.56), (0.76, 0.57, 0.42),
                          (0.55, 0.38, 0.26), (0.36, 0.24, 0.16))


@dataclass(frozen=True)
class PersonSpec:
    """A person to place: looks, floor position, heading (rad) and pose."""

    appearance: Appearance
    x: float
    y: float
    yaw: float
    pose: PoseName = "standing"


@dataclass(frozen=True)
class FurnitureSpec:
    """A furniture item (``sim.furnishings.furniture_parts`` kind) on the floor."""

    kind: str
    size: tuple[float, float, float]
    colour: Rgb
    x: float
    y: float
    yaw: float


@dataclass(frozen=True)
class SceneSpec:
    """Everything random about one frame; :func:`sample_scene` draws one from a seed."""

    people: tuple[PersonSpec, ...] = ()
    furniture: tuple[FurnitureSpec, ...] = ()
    depth: float = 7.0        # the far wall's x (the robot stands at the origin facing +x)
    half_width: float = 4.0   # side walls at y = +-half_width; the back wall at x = -1.5
    wall: Rgb = (0.85, 0.83, 0.78)
    floor: Rgb = (0.55, 0.45, 0.35)
    light: Light = field(default_factory=lambda: Light((0.3, -0.5, 1.0), (1, 1, 1), 0.6,
                                                       0.5, 0.1, False))
    head_pitch: float = 0.1   # rad, positive looks down (Pepper's HeadPitch joint)


@dataclass(frozen=True)
class Box:
    """One labelled instance: class index and inclusive pixel extents."""

    cls: int
    x0: int
    y0: int
    x1: int
    y1: int

    def yolo(self, width: int, height: int) -> str:
        """The YOLO label line ``cls cx cy w h`` (normalised)."""
        w, h = self.x1 - self.x0 + 1, self.y1 - self.y0 + 1
        return (f"{self.cls} {(self.x0 + w / 2) / width:.6f} {(self.y0 + h / 2) / height:.6f} "
                f"{w / width:.6f} {h / height:.6f}")

    @classmethod
    def from_yolo(cls, line: str, width: int, height: int) -> Box:
        """The box of a YOLO label line written by :meth:`yolo` (back to whole pixels)."""
        c, cx, cy, w, h = (float(v) for v in line.split())
        x0, y0 = round((cx - w / 2) * width), round((cy - h / 2) * height)
        return cls(int(c), x0, y0, x0 + round(w * width) - 1, y0 + round(h * height) - 1)


@dataclass
class Frame:
    """A rendered frame: RGB image, its boxes, and the decoded mask (for checks)."""

    rgb: np.ndarray
    boxes: list[Box]
    bodies: np.ndarray
    links: np.ndarray
    people: list[tuple[int, tuple[int, ...]]]  # (body id, face links) of each person


def _u(rng: np.random.Generator, lo: float, hi: float) -> float:
    return float(rng.uniform(lo, hi))


def _colour(rng: np.random.Generator) -> Rgb:
    return tuple(float(v) for v in rng.uniform(0.05, 0.95, 3))  # type: ignore[return-value]


def _person(rng: np.random.Generator, cfg: DataConfig, hfov: float) -> PersonSpec:
    d = _u(rng, *cfg.distance)
    a = _u(rng, -1, 1) * (hfov / 2 + math.radians(cfg.edge_margin_deg))
    x, y = d * math.cos(a), d * math.sin(a)
    to_camera = math.atan2(-y, -x)
    weights = np.asarray(cfg.view_weights, dtype=float)
    view = VIEWS[int(rng.choice(len(VIEWS), p=weights / weights.sum()))]
    yaw = to_camera + {"front": 0.0, "side": float(rng.choice([-1, 1])) * math.pi / 2,
                       "back": math.pi}[view] + _u(rng, -0.4, 0.4)
    height = _u(rng, 1.1, 1.95)
    look = Appearance(height, height * _u(rng, 0.22, 0.3), _colour(rng), _colour(rng),
                      SKINS[int(rng.integers(len(SKINS)))],
                      tuple(float(v) for v in rng.uniform(0.02, 0.6, 3)))  # type: ignore[arg-type]
    return PersonSpec(look, x, y, yaw, POSES[int(rng.integers(len(POSES)))])


def sample_scene(seed: int | np.random.SeedSequence, cfg: DataConfig, hfov: float) -> SceneSpec:
    """Draw a random room, light, furniture and people; ``hfov`` is the horizontal field of
    view (rad) of the camera."""
    rng = np.random.default_rng(seed)
    count = int(rng.integers(cfg.people_per_frame[0], cfg.people_per_frame[1] + 1))
    if rng.random() < cfg.empty_fraction:
        count = 0
    people: list[PersonSpec] = []
    for _ in range(20 * count):
        if len(people) == count:
            break
        cand = _person(rng, cfg, hfov)
        if all(math.hypot(cand.x - q.x, cand.y - q.y) > 0.7 for q in people):
            people.append(cand)
    furniture: list[FurnitureSpec] = []
    for q in people:  # most sitters get a seat under them
        if q.pose == "sitting" and rng.random() < 0.7:
            kind = str(rng.choice(["chair", "armchair", "sofa"]))
            c, s = math.cos(q.yaw), math.sin(q.yaw)
            furniture.append(FurnitureSpec(kind, FURNITURE_SIZES[kind], _colour(rng),
                                           q.x - 0.1 * c, q.y - 0.1 * s, q.yaw))
    kinds = sorted(FURNITURE_SIZES)
    n_furniture = int(rng.integers(cfg.furniture_per_frame[0], cfg.furniture_per_frame[1] + 1))
    for _ in range(20 * n_furniture):
        if len(furniture) >= n_furniture + sum(q.pose == "sitting" for q in people):
            break
        kind = kinds[int(rng.integers(len(kinds)))]
        size = tuple(v * _u(rng, 0.85, 1.15) for v in FURNITURE_SIZES[kind])
        d, a = _u(rng, 1.0, 6.5), _u(rng, -0.7, 0.7)
        x, y = d * math.cos(a), d * math.sin(a)
        if all(math.hypot(x - q.x, y - q.y) > 0.4 + max(size[:2]) / 2 for q in people):
            furniture.append(FurnitureSpec(kind, size, _colour(rng), x, y,  # type: ignore[arg-type]
                                           _u(rng, -math.pi, math.pi)))
    far_x = max([q.x for q in people] + [f.x for f in furniture] + [0.0])
    far_y = max([abs(q.y) for q in people] + [abs(f.y) for f in furniture] + [0.0])
    light = Light(((_u(rng, -1, 1)), _u(rng, -1, 1), _u(rng, 0.3, 1.5)),
                  tuple(float(v) for v in rng.uniform(0.75, 1.0, 3)),  # type: ignore[arg-type]
                  _u(rng, 0.35, 0.75), _u(rng, 0.3, 0.7), _u(rng, 0.0, 0.3),
                  bool(rng.random() < 0.2))
    return SceneSpec(tuple(people), tuple(furniture), max(_u(rng, 4, 8), far_x + 1.2),
                     max(_u(rng, 2, 4.5), far_y + 1.0), _colour(rng), _colour(rng), light,
                     _u(rng, *cfg.head_pitch))


def room_parts(spec: SceneSpec) -> list[Part]:
    """Floor and four walls (2.6 m) of the room around the robot."""
    back, t, h = -1.5, WALL_THICKNESS, 2.6
    length, mid = spec.depth - back, (spec.depth + back) / 2
    width = 2 * spec.half_width
    return [Part("box", (length, width, 0.01), spec.floor, (mid, 0, -0.005)),
            Part("box", (t, width, h), spec.wall, (spec.depth, 0, h / 2)),
            Part("box", (t, width, h), spec.wall, (back, 0, h / 2)),
            Part("box", (length, t, h), spec.wall, (mid, spec.half_width, h / 2)),
            Part("box", (length, t, h), spec.wall, (mid, -spec.half_width, h / 2))]


class DetectorScene:
    """A PyBullet DIRECT client holding the robot; renders :class:`SceneSpec` frames."""

    def __init__(self, cfg: DataConfig) -> None:
        self.cfg = cfg
        self.client = p.connect(p.DIRECT)
        self.robot = Robot(self.client)
        w, h = cfg.image.width, cfg.image.height
        vfov = math.radians(self.robot.camera.cfg.fov_deg)
        self.hfov = 2 * math.atan(math.tan(vfov / 2) * w / h)
        names = [p.getJointInfo(self.robot.body_id, j, physicsClientId=self.client)[1].decode()
                 for j in range(p.getNumJoints(self.robot.body_id, physicsClientId=self.client))]
        self._head_pitch = names.index("HeadPitch")

    def close(self) -> None:
        """Disconnect the PyBullet client."""
        p.disconnect(self.client)

    def sample(self, seed: int | np.random.SeedSequence) -> SceneSpec:
        """A random scene for this camera."""
        return sample_scene(seed, self.cfg, self.hfov)

    def _render(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        rgb, seg = self.robot.camera.frame_with_segmentation(self.cfg.image.width,
                                                             self.cfg.image.height)
        bodies, links = decode_segmentation(seg)
        return rgb, bodies, links

    @contextmanager
    def _built(self, spec: SceneSpec) -> Iterator[tuple[list[Person], list[int]]]:
        """The scene built in the client (its people and other bodies), removed on exit."""
        built = [build_body(self.client, "room", room_parts(spec))]
        for f in spec.furniture:
            parts, _ = furniture_parts(f.kind, *f.size, f.colour)
            built.append(build_body(self.client, f.kind, parts, (f.x, f.y, 0), f.yaw))
        people = [Person(self.client, q.appearance, q.x, q.y, q.yaw, q.pose, f"person_{i}")
                  for i, q in enumerate(spec.people)]
        self.robot.camera.set_lighting(spec.light.camera_kwargs())
        p.resetJointState(self.robot.body_id, self._head_pitch, spec.head_pitch,
                          physicsClientId=self.client)
        try:
            yield people, built
        finally:
            for body in built:
                p.removeBody(body, physicsClientId=self.client)
            for person in people:
                person.remove()

    def render(self, spec: SceneSpec) -> Frame:
        """Build the scene, render it, label it, and remove what was built."""
        with self._built(spec) as (people, built):
            ids = [(q.body_id, q.face_links) for q in people]
            rgb, bodies, links = self._render()
            boxes = self._label(spec, people, built, bodies, links)
        return Frame(rgb, boxes, bodies, links, ids)

    def people_in_frame(self, spec: SceneSpec) -> tuple[np.ndarray, list[tuple[int, Box, float]]]:
        """The frame of ``spec`` and, per visible person, their index in ``spec.people``,
        their box and the share of them visible (pixels over those rendered alone)."""
        seen = []
        with self._built(spec) as (people, built):
            rgb, bodies, _ = self._render()
            for i, person in enumerate(people):
                mine = bodies == person.body_id
                if mine.any():
                    others = [*built, *(o.body_id for o in people if o is not person)]
                    alone, _ = self._alone(person, others)
                    seen.append((i, _extent(mine, 0), float(mine.sum()) / max(1, alone)))
        return rgb, seen

    def _alone(self, person: Person, others: list[int]) -> tuple[int, int]:
        """Pixel counts of the person and its face rendered with every other body parked away."""
        poses = [p.getBasePositionAndOrientation(b, physicsClientId=self.client) for b in others]
        for b, (pos, orn) in zip(others, poses, strict=True):
            p.resetBasePositionAndOrientation(b, (pos[0], pos[1], pos[2] - FAR), orn,
                                              physicsClientId=self.client)
        try:
            _, bodies, links = self._render()
        finally:
            for b, (pos, orn) in zip(others, poses, strict=True):
                p.resetBasePositionAndOrientation(b, pos, orn, physicsClientId=self.client)
        mine = bodies == person.body_id
        return int(mine.sum()), int((mine & np.isin(links, person.face_links)).sum())

    def _label(self, spec: SceneSpec, people: list[Person], built: list[int],
               bodies: np.ndarray, links: np.ndarray) -> list[Box]:
        """Boxes from the mask, filtered by the rule in docs/detector.md."""
        cfg, boxes = self.cfg, []
        eye = self.robot.camera.pose()[0]
        for q, person in zip(spec.people, people, strict=True):
            mine = bodies == person.body_id
            if not mine.any():
                continue
            face = mine & np.isin(links, person.face_links)
            others = [*built, *(o.body_id for o in people if o is not person)]
            alone, alone_face = self._alone(person, others)
            box = _extent(mine, 0)
            if (box.y1 - box.y0 + 1 >= cfg.min_box_px and box.x1 - box.x0 + 1 >= cfg.min_width_px
                    and mine.sum() >= cfg.min_visible_fraction * alone):
                boxes.append(box)
            to_camera = math.atan2(eye[1] - q.y, eye[0] - q.x)
            angle = abs(math.remainder(to_camera - q.yaw, 2 * math.pi))
            if not face.any() or math.degrees(angle) > cfg.face_max_angle_deg:
                continue
            fbox = _extent(face, 1)
            if (min(fbox.y1 - fbox.y0, fbox.x1 - fbox.x0) + 1 >= cfg.min_face_px
                    and face.sum() >= cfg.min_visible_fraction * alone_face):
                boxes.append(fbox)
        return boxes


def _extent(mask: np.ndarray, cls: int) -> Box:
    """The tight pixel box of a non-empty boolean mask."""
    rows, cols = np.flatnonzero(mask.any(axis=1)), np.flatnonzero(mask.any(axis=0))
    return Box(cls, int(cols[0]), int(rows[0]), int(cols[-1]), int(rows[-1]))


def draw_boxes(rgb: np.ndarray, boxes: list[Box]) -> np.ndarray:
    """A BGR copy of ``rgb`` with person boxes in green and face boxes in red."""
    img = cv2.cvtColor(rgb, cv2.COLOR_RGB2BGR)
    for b in boxes:
        colour = (0, 200, 0) if b.cls == 0 else (0, 0, 230)
        cv2.rectangle(img, (b.x0, b.y0), (b.x1, b.y1), colour, 1)
        cv2.putText(img, CLASSES[b.cls], (b.x0, max(b.y0 - 2, 8)), cv2.FONT_HERSHEY_SIMPLEX,
                    0.3, colour, 1)
    return img


def encode_png(img_bgr: np.ndarray) -> bytes:
    """PNG file bytes of a BGR image."""
    ok, buf = cv2.imencode(".png", img_bgr)
    if not ok:
        raise RuntimeError("PNG encoding failed")
    return buf.tobytes()


def write_dataset(out: Path, cfg: DataConfig,
                  progress: Callable[[int], None] | None = None) -> dict[str, int]:
    """Render every split into ``out`` (resumable: frames whose label exists are skipped).

    Frame ``i`` of split ``k`` (train 0, val 1, test 2) is seeded with
    ``SeedSequence([seed, k, i])``, so the splits never share a seed. Returns the number of
    frames rendered now, per split; ``progress(n)`` is called after each frame.
    """
    counts = {s: getattr(cfg.splits, s) for s in SPLITS}
    (out / "examples").mkdir(parents=True, exist_ok=True)
    scene = DetectorScene(cfg)
    done = dict.fromkeys(SPLITS, 0)
    w, h = cfg.image.width, cfg.image.height
    try:
        for k, split in enumerate(SPLITS):
            images, labels = out / "images" / split, out / "labels" / split
            images.mkdir(parents=True, exist_ok=True)
            labels.mkdir(parents=True, exist_ok=True)
            for i in range(counts[split]):
                label = labels / f"{i:06d}.txt"
                example = split == "train" and i < cfg.examples
                if label.exists() and (images / f"{i:06d}.png").exists():
                    if progress:
                        progress(1)
                    continue
                frame = scene.render(scene.sample(np.random.SeedSequence([cfg.seed, k, i])))
                atomic_write_bytes(images / f"{i:06d}.png",
                              encode_png(cv2.cvtColor(frame.rgb, cv2.COLOR_RGB2BGR)))
                if example:
                    atomic_write_bytes(out / "examples" / f"{split}_{i:06d}.png",
                                  encode_png(draw_boxes(frame.rgb, frame.boxes)))
                text = "".join(b.yolo(w, h) + "\n" for b in frame.boxes)
                atomic_write_bytes(label, text.encode())
                done[split] += 1
                if progress:
                    progress(1)
    finally:
        scene.close()
    meta = {"path": str(out.resolve()), "train": "images/train", "val": "images/val",
            "test": "images/test", "names": dict(enumerate(CLASSES))}
    atomic_write_bytes(out / "data.yaml", yaml.safe_dump(meta, sort_keys=False).encode())
    return done
