"""The facing model's data: people rendered from the robot's head camera, cut out by their
box and labelled with where they look.

Scenes come from the detector's renderer (:class:`perception.detector.training.data.
DetectorScene`: random rooms, furniture, standing, sitting and arm-raising people) with the
recipe's distances and head counts; every person's heading is then drawn uniformly, so all
facing angles are equally common. A person is kept when their box is at least
``min_box_px`` high and at least ``min_visible_fraction`` of them shows. The label is the
facing angle relative to the line from the person to the camera (see
:mod:`perception.facing.model`). Each split is written as ``{split}.npz`` (``crops``
uint8 (N, H, W, 3), ``angles`` rad, ``poses``, ``distances`` m) once it is complete, so an
interrupted run resumes at the first missing split.
"""

from __future__ import annotations

import dataclasses
import io
import json
import math
import time
import zipfile
from pathlib import Path

import numpy as np

from core.checkpoint import atomic_write_bytes
from core.errors import UserError
from perception.detector.config import load_detector_config
from perception.detector.training.data import SPLITS, DetectorScene, SceneSpec
from perception.facing.config import FacingDataConfig
from perception.facing.model import crop_person

POSE_IDS = ("standing", "sitting", "arms_raised")


def _spun(spec: SceneSpec, rng: np.random.Generator) -> SceneSpec:
    """``spec`` with every person's heading drawn uniformly."""
    people = tuple(dataclasses.replace(q, yaw=float(rng.uniform(-math.pi, math.pi)))
                   for q in spec.people)
    return dataclasses.replace(spec, people=people)


def make_scene(cfg: FacingDataConfig) -> DetectorScene:
    """The detector's renderer with this recipe's distances and head counts, no empty frames."""
    data = load_detector_config().data.model_copy(update={
        "distance": cfg.distance, "people_per_frame": cfg.people_per_frame,
        "empty_fraction": 0.0})
    return DetectorScene(data)


Example = tuple[np.ndarray, float, str, float]


def frame_examples(scene: DetectorScene, seed: np.random.SeedSequence, cfg: FacingDataConfig
                   ) -> list[Example]:
    """The examples of the frame drawn from ``seed`` (headings drawn uniformly)."""
    rng = np.random.default_rng(seed.spawn(1)[0])
    return spec_examples(scene, _spun(scene.sample(seed), rng), cfg)


def spec_examples(scene: DetectorScene, spec: SceneSpec, cfg: FacingDataConfig
                  ) -> list[Example]:
    """(crop, facing angle, pose, distance) of each usable person in the frame of ``spec``."""
    rgb, seen = scene.people_in_frame(spec)
    eye = scene.robot.camera.pose()[0]
    out = []
    for i, box, visible in seen:
        if box.y1 - box.y0 + 1 < cfg.min_box_px or visible < cfg.min_visible_fraction:
            continue
        q = spec.people[i]
        to_camera = math.atan2(eye[1] - q.y, eye[0] - q.x)
        angle = math.remainder(q.yaw - to_camera, 2 * math.pi)
        crop = crop_person(rgb, (box.x0, box.y0, box.x1, box.y1), cfg.crop, cfg.pad)
        out.append((crop, angle, q.pose, math.hypot(q.x - eye[0], q.y - eye[1])))
    return out


def write_facing_dataset(out: Path, cfg: FacingDataConfig) -> dict[str, int]:
    """Render every split of the recipe missing from ``out``; crops per split."""
    out.mkdir(parents=True, exist_ok=True)
    counts: dict[str, int] = {}
    scene = make_scene(cfg)
    start = time.perf_counter()
    try:
        for k, split in enumerate(SPLITS):
            path = out / f"{split}.npz"
            if path.exists():
                counts[split] = len(np.load(path)["angles"])
                continue
            rows = [r for i in range(getattr(cfg.splits, split))
                    for r in frame_examples(scene, np.random.SeedSequence([cfg.seed, k, i]), cfg)]
            buf = io.BytesIO()
            np.savez_compressed(
                buf, crops=np.stack([r[0] for r in rows]) if rows else np.zeros((0, 1, 1, 3)),
                angles=np.array([r[1] for r in rows], np.float32),
                poses=np.array([POSE_IDS.index(r[2]) for r in rows], np.int64),
                distances=np.array([r[3] for r in rows], np.float32))
            atomic_write_bytes(path, buf.getvalue())
            counts[split] = len(rows)
    finally:
        scene.close()
    meta = {"recipe": cfg.model_dump(mode="json"), "crops": counts,
            "seconds_now": round(time.perf_counter() - start, 1)}
    atomic_write_bytes(out / "meta.json", json.dumps(meta, indent=1).encode())
    return counts


def load_split(root: Path, split: str) -> dict[str, np.ndarray]:
    """One split of a facing data set (no pickled objects are read); an unreadable one
    raises a :class:`~core.errors.UserError` naming it."""
    path = root / f"{split}.npz"
    try:
        with np.load(path, allow_pickle=False) as data:
            return {k: data[k] for k in data.files}
    except (OSError, ValueError, EOFError, zipfile.BadZipFile) as exc:
        raise UserError(f"{path}: not a readable facing data split ({exc}); render it "
                        "with `companion data facing`") from None
