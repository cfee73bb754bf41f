"""The VQG data set: rendered household frames, their scene graphs and grounded questions.

:func:`write_vqg_dataset` writes ``images/{split}/NNNNNN.png``, ``scenes/{split}/NNNNNN.json``,
``questions/{split}.jsonl`` (one ``{"id", "questions"}`` object per line), ``meta.json`` and
``examples/`` (a few train frames with their questions listed in ``examples.txt``). Frame
``i`` of split ``k`` (train 0, val 1, test 2) is drawn from ``SeedSequence([seed, k, i])``;
files are written atomically and finished frames are skipped, so a run can be resumed.
The recipe is ``config/vqg_data.yaml`` (docs/vqg_data.md).
"""

from __future__ import annotations

import json
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np
from tqdm import tqdm

from core.checkpoint import atomic_write_bytes
from perception.vqg.scene import SceneGraph, load_scene
from perception.vqg.training.data_config import SPLITS, VqgDataConfig, load_vqg_data_config
from perception.vqg.training.frames_io import collect, frame_done, questions_for, write_frame
from perception.vqg.training.household_data import write_household_frames
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


def write_vqg_dataset(out: Path, cfg: VqgDataConfig, splits: dict[str, int],
                      progress: bool | Callable[[int], None] = True,
                      household: dict[str, int] | None = None) -> dict[str, int]:
    """Render ``splits`` (split name -> frames) into ``out``, then the ``household`` frames
    of the shipped worlds (split name -> frames; none by default); return the frames
    rendered now, per split.

    ``progress`` is True for a tqdm bar, False for none, or a callback given 1 per frame."""
    out = Path(out)
    household = household or {}
    bar = tqdm(total=sum(splits.values()) + sum(household.values()), unit="frame",
               disable=None if progress is True else True)  # None: not off a terminal
    tick = progress if callable(progress) else bar.update
    renderer = make_renderer(cfg)
    done = dict.fromkeys(splits, 0)
    start = time.perf_counter()
    try:
        for split, n in splits.items():
            k = SPLITS.index(split)
            for i in range(n):
                name = f"{i:06d}"
                if not frame_done(out, split, name):
                    seed = np.random.SeedSequence([cfg.seed, k, i])
                    rgb, graph = render_scene(seed, cfg, renderer)
                    write_frame(out, split, name, rgb, graph, questions_for(graph, seed, cfg))
                    done[split] += 1
                tick(1)
        homes = write_household_frames(out, cfg, household, tick)
    finally:
        renderer.close()
        bar.close()
    seconds = time.perf_counter() - start
    for split in {**splits, **household}:
        collect(out, split)
        done[split] = done.get(split, 0) + homes.get(split, 0)
    _examples(out, cfg.examples if "train" in splits else 0, household.get("train", 0))
    meta = {"recipe": cfg.model_dump(mode="json"), "seed": cfg.seed, "counts": splits,
            "household_counts": household, "rendered_now": done,
            "seconds_now": round(seconds, 1),
            "frames_per_s": round(sum(done.values()) / seconds, 3) if sum(done.values()) else None}
    atomic_write_bytes(out / "meta.json", json.dumps(meta, indent=1).encode())
    return done


def _examples(out: Path, count: int, household: int) -> None:
    """The first ``count`` train frames of each source (rendered scenes, household frames
    when there are ``household`` of them) copied to ``examples/`` with their questions."""
    folder = out / "examples"
    folder.mkdir(exist_ok=True)
    text = []
    names = [f"{i:06d}" for i in range(count)] + [f"h{i:06d}" for i in range(min(count, household))]
    for name in names:
        if not frame_done(out, "train", name):
            continue
        image = (out / "images" / "train" / f"{name}.png").read_bytes()
        atomic_write_bytes(folder / f"train_{name}.png", image)
        record = json.loads((out / "questions" / "train" / f"{name}.json").read_text())
        graph = load_scene(out / "scenes" / "train" / f"{name}.json")
        text.append(f"== train_{name}.png  room {graph.room}, occasion {graph.occasion}, "
                    f"{len(graph.nodes)} nodes: {', '.join(n.id for n in graph.nodes)}")
        text += [f"  {q}" for q in record["questions"]]
    atomic_write_bytes(folder / "examples.txt", ("\n".join(text) + "\n").encode())
