"""The VQG data set: rendered household frames, their scene graphs and grounded questions.

:func:`write_vqg_dataset` writes ``images/{split}/NNNNNN.png``, ``scenes/{split}/NNNNNN.json``,
``questions/{split}.jsonl`` (one ``{"id", "questions"}`` object per line), ``meta.json`` and
``examples/`` (a few train frames with their questions listed in ``examples.txt``). Frame
``i`` of split ``k`` (train 0, val 1, test 2) is drawn from ``SeedSequence([seed, k, i])``;
files are written atomically and finished frames are skipped, so a run can be resumed.
The recipe is ``app/defaults/vqg_data.yaml`` (docs/vqg_data.md).
"""

from __future__ import annotations

import json
import time
from collections.abc import Callable
from pathlib import Path

import cv2
import numpy as np
from tqdm import tqdm

from app.core.checkpoint import atomic_write_bytes
from perception.detector.training.data import encode_png
from perception.vqg.scene import SceneGraph, load_scene
from perception.vqg.training.data_config import SPLITS, VqgDataConfig, load_vqg_data_config
from perception.vqg.training.facts import generate_questions
from perception.vqg.training.layout import sample_plan
from perception.vqg.training.render import VqgRenderer


def make_renderer(cfg: VqgDataConfig) -> VqgRenderer:
    """A renderer for ``cfg`` (close it when done)."""
    return VqgRenderer(cfg.scene.width, cfg.scene.height, cfg.visibility)


def render_scene(seed: int | np.random.SeedSequence, cfg: VqgDataConfig | None = None,
                 renderer: VqgRenderer | None = None) -> tuple[np.ndarray, SceneGraph]:
    """The RGB head-camera frame (H, W, 3 uint8) of the scene drawn from ``seed`` and the
    graph of what it shows. Pass a ``renderer`` to render many scenes in one client."""
    cfg = cfg or load_vqg_data_config()
    own = renderer is None
    r = renderer or make_renderer(cfg)
    try:
        return r.render_plan(sample_plan(seed, cfg.scene, r.hfov))
    finally:
        if own:
            r.close()


def questions_for(graph: SceneGraph, seed: np.random.SeedSequence, cfg: VqgDataConfig) -> list[str]:
    """The data set's questions about ``graph`` (seeded by the frame's seed)."""
    q = cfg.questions
    rng = np.random.default_rng(seed.spawn(1)[0])
    return generate_questions(graph, rng, q.max_frames, q.paraphrases, q.max_questions,
                              q.fixed_wording)


def write_vqg_dataset(out: Path, cfg: VqgDataConfig, splits: dict[str, int],
                      progress: bool | Callable[[int], None] = True) -> dict[str, int]:
    """Render ``splits`` (split name -> frames) into ``out``; return the frames rendered now.

    ``progress`` is True for a tqdm bar, False for none, or a callback given 1 per frame."""
    out = Path(out)
    bar = tqdm(total=sum(splits.values()), unit="frame", disable=progress is not True)
    tick = progress if callable(progress) else bar.update
    renderer = make_renderer(cfg)
    done = dict.fromkeys(splits, 0)
    start = time.perf_counter()
    try:
        for split, n in splits.items():
            k = SPLITS.index(split)
            for sub in ("images", "scenes", "questions"):
                (out / sub / split).mkdir(parents=True, exist_ok=True)
            for i in range(n):
                name = f"{i:06d}"
                png = out / "images" / split / f"{name}.png"
                scene = out / "scenes" / split / f"{name}.json"
                qfile = out / "questions" / split / f"{name}.json"
                if not (png.exists() and scene.exists() and qfile.exists()):
                    seed = np.random.SeedSequence([cfg.seed, k, i])
                    rgb, graph = render_scene(seed, cfg, renderer)
                    record = {"id": name, "questions": questions_for(graph, seed, cfg)}
                    atomic_write_bytes(png, encode_png(cv2.cvtColor(rgb, cv2.COLOR_RGB2BGR)))
                    atomic_write_bytes(scene, graph.to_json().encode())
                    atomic_write_bytes(qfile, json.dumps(record).encode())
                    done[split] += 1
                tick(1)
            _collect(out, split, n)
    finally:
        renderer.close()
        bar.close()
    seconds = time.perf_counter() - start
    _examples(out, cfg.examples if "train" in splits else 0)
    meta = {"recipe": cfg.model_dump(mode="json"), "seed": cfg.seed, "counts": splits,
            "rendered_now": done, "seconds_now": round(seconds, 1),
            "frames_per_s": round(sum(done.values()) / seconds, 3) if sum(done.values()) else None}
    atomic_write_bytes(out / "meta.json", json.dumps(meta, indent=1).encode())
    return done


def _collect(out: Path, split: str, n: int) -> None:
    """``questions/{split}.jsonl`` from the per-frame question files."""
    folder = out / "questions" / split
    lines = [(folder / f"{i:06d}.json").read_text(encoding="utf-8") + "\n" for i in range(n)]
    atomic_write_bytes(out / "questions" / f"{split}.jsonl", "".join(lines).encode())


def _examples(out: Path, count: int) -> None:
    """The first ``count`` train frames copied to ``examples/`` with their questions listed."""
    folder = out / "examples"
    folder.mkdir(exist_ok=True)
    text = []
    for i in range(min(count, len(list((out / "images" / "train").glob("*.png"))))):
        name = f"{i:06d}"
        image = (out / "images" / "train" / f"{name}.png").read_bytes()
        atomic_write_bytes(folder / f"train_{name}.png", image)
        record = json.loads((out / "questions" / "train" / f"{name}.json").read_text())
        graph = load_scene(out / "scenes" / "train" / f"{name}.json")
        text.append(f"== train_{name}.png  room {graph.room}, occasion {graph.occasion}, "
                    f"{len(graph.nodes)} nodes: {', '.join(n.id for n in graph.nodes)}")
        text += [f"  {q}" for q in record["questions"]]
    atomic_write_bytes(folder / "examples.txt", ("\n".join(text) + "\n").encode())
