"""Programmatic evaluation of the question generator (thesis §4.3, eqs. 4.3-4.5).

For each of N held-out images, K latent codes are drawn from the prior and decoded (one
question each); the *distinct* question strings of an image form its set S. Over all sets:

* ``distinct_per_image``: mean size of S (thesis 15.7 of 100 samples).
* ``dm`` (Diverse Meaning, eq. 4.3): share of questions in S whose semantic frame
  (:func:`perception.vqg.questions.frame_key` of the parsed question) differs from the frame
  of every other question in the same S; an unparseable question scores 0.
* ``ri`` (Relatedness with the Image, eq. 4.4): share of questions in S that parse and are
  grounded in the image's scene graph (:func:`~perception.vqg.questions.is_grounded`).
* ``rs`` (Relatedness with the Scene, eq. 4.5, as a share): share that parse and are on the
  scene's topic (:func:`~perception.vqg.questions.is_on_topic`).
* ``bleu``: sacreBLEU corpus BLEU of every question in every S against all the reference
  questions of its image (a variable number of references).
* ``grounded5_share``: share of the images showing a person or an object whose S holds at
  least five grounded questions.
* ``latency_ms``: median wall time of ``ask(frame, 10)`` on a full-size test frame.

The shares pool the questions of all images (the thesis's 785 sentences).
"""

from __future__ import annotations

import csv
import statistics
import time
from collections import Counter
from dataclasses import dataclass
from pathlib import Path
from typing import Any, ClassVar

import cv2
import numpy as np
import sacrebleu
import torch

from perception.vqg.config import VqgConfig
from perception.vqg.generator import VqgQuestionGenerator, save_vqg
from perception.vqg.model import VqgModel
from perception.vqg.questions import frame_key, is_grounded, is_on_topic, parse_question
from perception.vqg.scene import SceneGraph, load_scene
from perception.vqg.training.dataset import VqgDataError, read_image, read_questions
from textnets.loop import Run
from textnets.vocab import Vocab

MODEL_FILE = "vqg.pt"
METRICS = ("distinct_per_image", "dm", "ri", "rs")
RICH_GROUNDED = 5  # grounded5_share: frames showing a person or object with this many or more


@dataclass
class Item:
    """One held-out image: model input, scene graph, reference questions, file."""

    image: torch.Tensor
    scene: SceneGraph
    refs: list[str]
    path: Path


def load_items(cfg: VqgConfig, split: str, n: int) -> list[Item]:
    """The first ``n`` images of a split with their scene graphs and questions; half of
    them household frames (``h`` ids) when the split holds both kinds."""
    d = cfg.data
    root = d.resolved_dir()
    ids, questions = read_questions(root, split)
    homes = [k for k, i in enumerate(ids) if i.startswith("h")]
    scenes = [k for k, i in enumerate(ids) if not i.startswith("h")]
    half = n // 2 if homes and scenes else n
    chosen = scenes[:half] + homes[:n - min(half, len(scenes))] if homes else scenes[:n]
    items = []
    for i, qs in ((ids[k], questions[k]) for k in chosen):
        path = root / "images" / split / f"{i}.png"
        scene_path = root / "scenes" / split / f"{i}.json"
        try:
            scene = load_scene(scene_path)
        except (OSError, ValueError, KeyError) as exc:
            raise VqgDataError(f"{scene_path}: cannot read the scene graph ({exc})") from None
        items.append(Item(read_image(path, d.image_width, d.image_height), scene,
                          [" ".join(q) for q in qs], path))
    return items


def judge(questions: list[str], scene: SceneGraph) -> dict[str, list[bool]]:
    """Per question of one distinct set: dm, ri and rs verdicts (see the module docstring)."""
    frames = [parse_question(q) for q in questions]
    keys = [frame_key(f) if f is not None else None for f in frames]
    counts = Counter(k for k in keys if k is not None)
    return {"dm": [k is not None and counts[k] == 1 for k in keys],
            "ri": [f is not None and is_grounded(f, scene) for f in frames],
            "rs": [f is not None and is_on_topic(f, scene) for f in frames],
            "parsed": [f is not None for f in frames]}


def question_metrics(gen: VqgQuestionGenerator, items: list[Item], samples: int,
                     bleu: bool = True) -> dict[str, Any]:
    """The metrics of the module docstring over ``items`` with ``samples`` codes each."""
    flags: dict[str, list[bool]] = {"dm": [], "ri": [], "rs": [], "parsed": []}
    hyps: list[str] = []
    refs: list[list[str]] = []
    sizes, examples, rich = [], [], []
    for item in items:
        distinct = gen.questions(item.image, samples)
        sizes.append(len(distinct))
        verdicts = judge(distinct, item.scene)
        for k, v in verdicts.items():
            flags[k] += v
        if any(n.category in ("person", "object") for n in item.scene.nodes):
            rich.append(sum(verdicts["ri"]) >= RICH_GROUNDED)
        hyps += distinct
        refs += [item.refs] * len(distinct)
        if len(examples) < 5:
            examples.append({"image": str(item.path), "questions": distinct})
    n = max(1, len(hyps))
    out: dict[str, Any] = {"distinct_per_image": sum(sizes) / max(1, len(sizes))}
    out |= {k: sum(v) / n for k, v in flags.items()}
    out["grounded5_share"] = sum(rich) / len(rich) if rich else None
    if bleu:
        width = max((len(r) for r in refs), default=0)
        streams = [[r[j] if j < len(r) else None for r in refs] for j in range(width)]
        out["bleu"] = sacrebleu.corpus_bleu(hyps, streams).score if hyps else 0.0
    out |= {"images": len(items), "samples": samples, "questions": len(hyps),
            "examples": examples}
    return out


def selection_score(m: dict[str, Any], distinct_bar: float) -> float:
    """Model selection: ``min(1, distinct / bar) + dm + ri + rs`` (at most 4)."""
    return min(1.0, m["distinct_per_image"] / distinct_bar) + m["dm"] + m["ri"] + m["rs"]


def latency_ms(gen: VqgQuestionGenerator, frame: np.ndarray, n: int, runs: int) -> float:
    """Median wall time (ms) of ``ask(frame, n)`` over ``runs`` calls (after one warm-up)."""
    gen.ask(frame, n)
    times = []
    for _ in range(runs):
        t = time.perf_counter()
        gen.ask(frame, n)
        times.append(1000.0 * (time.perf_counter() - t))
    return statistics.median(times)


def evaluate(model: Path, cfg: VqgConfig, images: int, samples: int,
             split: str = "test") -> dict[str, Any]:
    """All metrics of the module docstring on ``split`` (the held-out test images; "val"
    to tune decoding settings without looking at them), with the bars checked."""
    gen = VqgQuestionGenerator.load(model, seed=cfg.train.seed, decode=cfg.decode)
    items = load_items(cfg, split, images)
    if not items:
        raise VqgDataError(f"{cfg.data.resolved_dir()}: the {split} split has no images")
    out = question_metrics(gen, items, samples)
    frame = cv2.imread(str(items[0].path), cv2.IMREAD_COLOR)[..., ::-1].copy()
    out["latency_ms"] = latency_ms(gen, frame, cfg.eval.latency_n, cfg.eval.latency_runs)
    bars = cfg.eval.bars
    out["pass"] = {k: (out[k] <= v if k == "latency_ms" else out[k] >= v)
                   for k, v in bars.items() if k in out}
    out["model"], out["split"] = str(model), split
    out["verifier"] = None if gen.verifier is None else str(cfg.decode.verifier_path())
    return out


class Selector:
    """Validates the live model on a few validation images and keeps the best as ``vqg.pt``.

    Each validation appends a row to ``valid_log.csv``; on resume, rows past the checkpoint
    are dropped and the best score is taken from the rows kept.
    """

    FIELDS: ClassVar[list[str]] = ["phase", "step", *METRICS, "score", "best", "wall_s"]

    def __init__(self, run: Run, model: VqgModel, vocab: Vocab, items: list[Item]) -> None:
        self.run, self.model, self.vocab, self.items = run, model, vocab, items
        self.path, self.log = run.out_dir / MODEL_FILE, run.out_dir / "valid_log.csv"
        state = run.state or {}

        def kept(row: list[str]) -> bool:   # validations up to the checkpoint
            return row[0] in run.done or (row[0] == state.get("phase")
                                          and int(row[1]) <= state["step"])

        run.folder.open_log(self.log.name, self.FIELDS, kept).close()   # rewritten whole
        with self.log.open(newline="") as fh:
            rows = list(csv.DictReader(fh))
        self.best_row = max((_selected(r) for r in rows), key=lambda r: r["score"],
                            default=None)
        self.best = self.best_row["score"] if self.best_row else -1.0

    def __call__(self, phase: str, step: int) -> None:
        """Validate now; export the model when it beats the best so far."""
        cfg = self.run.cfg
        size = (cfg.data.image_width, cfg.data.image_height)
        gen = VqgQuestionGenerator(self.model, self.vocab, size, cfg.decode,
                                   seed=cfg.train.seed)
        m = question_metrics(gen, self.items, cfg.train.select_samples, bleu=False)
        score = selection_score(m, cfg.eval.bars["distinct_per_image"])
        row = {"phase": phase, "step": step, **{k: f"{m[k]:.4f}" for k in METRICS},
               "score": f"{score:.4f}", "best": int(score > self.best),
               "wall_s": f"{self.run.wall():.1f}"}
        if score > self.best:
            self.best, self.best_row = score, _selected(row)
            save_vqg(self.path, self.model, self.vocab, cfg,
                     {"phase": phase, "step": step, "seed": cfg.train.seed,
                      "valid": {k: m[k] for k in METRICS}, "score": score})
        with self.log.open("a", newline="") as fh:
            csv.DictWriter(fh, self.FIELDS).writerow(row)

    def best_meta(self) -> dict | None:
        """The validation row of the exported model."""
        return self.best_row


def _selected(row: dict[str, Any]) -> dict[str, Any]:
    return {"phase": row["phase"], "step": int(row["step"]), "score": float(row["score"]),
            **{k: float(row[k]) for k in METRICS}}


