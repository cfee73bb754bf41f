"""One frame of the VQG data set on disk: its image, scene graph and questions.

Frame ``name`` of a split is ``images/{split}/{name}.png``, ``scenes/{split}/{name}.json``
and ``questions/{split}/{name}.json`` (``{"id", "questions"}``), each written atomically;
``questions/{split}.jsonl`` gathers the split's question records once it is complete.
"""

from __future__ import annotations

import json
from pathlib import Path

import cv2
import numpy as np

from core.checkpoint import atomic_write_bytes
from perception.detector.training.data import encode_png
from perception.vqg.scene import SceneGraph
from perception.vqg.training.data_config import VqgDataConfig
from perception.vqg.training.facts import generate_questions


def questions_for(graph: SceneGraph, seed: np.random.SeedSequence, cfg: VqgDataConfig) -> list[str]:
    """The data set's questions about ``graph`` (seeded by the frame's seed)."""
    q = cfg.questions
    rng = np.random.default_rng(seed.spawn(1)[0])
    return generate_questions(graph, rng, q.max_frames, q.paraphrases, q.max_questions,
                              q.fixed_wording)


def _paths(out: Path, split: str, name: str) -> tuple[Path, Path, Path]:
    return (out / "images" / split / f"{name}.png", out / "scenes" / split / f"{name}.json",
            out / "questions" / split / f"{name}.json")


def frame_done(out: Path, split: str, name: str) -> bool:
    """Whether all three files of frame ``name`` exist."""
    return all(path.exists() for path in _paths(out, split, name))


def write_frame(out: Path, split: str, name: str, rgb: np.ndarray, graph: SceneGraph,
                questions: list[str]) -> None:
    """Write frame ``name`` (RGB uint8) with its scene graph and questions."""
    png, scene, qfile = _paths(out, split, name)
    for path in (png, scene, qfile):
        path.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_bytes(png, encode_png(cv2.cvtColor(rgb, cv2.COLOR_RGB2BGR)))
    atomic_write_bytes(scene, graph.to_json().encode())
    atomic_write_bytes(qfile, json.dumps({"id": name, "questions": questions}).encode())


def collect(out: Path, split: str) -> None:
    """``questions/{split}.jsonl`` from the split's per-frame question files, in name order
    (the rendered scenes, then the ``h``-prefixed household frames)."""
    folder = out / "questions" / split
    lines = [path.read_text(encoding="utf-8") + "\n" for path in sorted(folder.glob("*.json"))]
    atomic_write_bytes(out / "questions" / f"{split}.jsonl", "".join(lines).encode())
