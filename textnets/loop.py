"""The bookkeeping shared by every training phase: checkpoints, CSV logs, progress, resume.

One ``checkpoint.pt`` holds the weights of all networks, the finished phases and, for the
phase under way, its step, optimizers, batch samplers, RNG state and extra values. It is
written atomically every ``checkpoint_every`` steps, at the end of each phase and on Ctrl-C;
``--resume`` continues from it. Each phase appends to ``log_<phase>.csv`` (means over
``log_every`` steps, flushed at once); on resume, rows past the checkpoint are dropped.
"""

from __future__ import annotations

import csv
import math
import time
from collections import defaultdict
from collections.abc import Callable
from pathlib import Path
from typing import Any

import torch
from torch import nn
from tqdm import tqdm

from app.core.checkpoint import atomic_torch_save, claim_run_folder
from app.core.errors import UserError
from dialogue.style.config import StyleConfig
from dialogue.style.training.data import BatchSampler

StepFn = Callable[[int], dict[str, float]]


class Run:
    """A training run folder and its checkpoint (see the module docstring)."""

    def __init__(self, cfg: StyleConfig, out_dir: Path, nets: dict[str, nn.Module],
                 resume: bool, progress: bool, name: str = "style") -> None:
        self.cfg, self.out_dir, self.nets, self.progress = cfg, out_dir, nets, progress
        self.name = name  # shown on the progress bars
        self.ckpt_path = out_dir / "checkpoint.pt"
        claim_run_folder(out_dir, self.ckpt_path, resume)
        self.state: dict[str, Any] | None = None
        self.done: list[str] = []
        self.wall_offset = 0.0
        self.start = time.perf_counter()
        if self.ckpt_path.exists():
            self.state = torch.load(self.ckpt_path, map_location="cpu", weights_only=True)
            self._load_nets()
            self.done = list(self.state["done"])
            self.wall_offset = float(self.state["wall_s"])

    def _load_nets(self) -> None:
        """Load every network from the checkpoint, or say why this run cannot go on."""
        saved = self.state["nets"]
        missing = sorted(set(self.nets) - set(saved))
        if missing:
            raise UserError(f"{self.ckpt_path}: holds no {', '.join(missing)} (it was written "
                            "by an older version of this training); start a new run folder")
        for name, net in self.nets.items():
            try:
                net.load_state_dict(saved[name])
            except RuntimeError as exc:
                raise UserError(f"{self.ckpt_path}: its {name} weights do not fit this "
                                f"config ({str(exc).splitlines()[0]}); resume with the run's "
                                "own config or start a new run folder") from exc

    def wall(self) -> float:
        """Seconds of training so far, across resumes."""
        return self.wall_offset + time.perf_counter() - self.start

    def save(self, phase: str | None, step: int = 0, optimizers: dict | None = None,
             samplers: dict | None = None, extra: dict | None = None,
             rng: torch.Tensor | None = None) -> None:
        """Write the checkpoint atomically (``samplers`` maps names to their states)."""
        atomic_torch_save({
            "nets": {k: v.state_dict() for k, v in self.nets.items()}, "done": self.done,
            "phase": phase, "step": step,
            "optimizers": {k: v.state_dict() for k, v in (optimizers or {}).items()},
            "samplers": samplers or {},
            "torch_rng": torch.get_rng_state() if rng is None else rng,
            "extra": extra or {}, "wall_s": self.wall(),
        }, self.ckpt_path)

    def finish(self, phase: str) -> None:
        """Mark ``phase`` done and checkpoint."""
        self.done.append(phase)
        self.save(None)

    def loop(self, phase: str, total: int, step_fn: StepFn, fields: list[str],
             optimizers: dict[str, torch.optim.Optimizer], samplers: dict[str, BatchSampler],
             extra: dict | None = None, on_eval: Callable[[int], None] | None = None,
             eval_every: int | None = None) -> None:
        """Run ``step_fn(step)`` for the remaining steps of ``phase``.

        ``extra`` is a mutable dict saved with the checkpoint (e.g. the best score so far);
        ``on_eval(step)`` runs every ``eval_every`` steps.
        """
        tc = self.cfg.train
        extra = {} if extra is None else extra
        start = 0
        if self.state is not None and self.state["phase"] == phase:
            start = int(self.state["step"])
            for k, opt in optimizers.items():
                opt.load_state_dict(self.state["optimizers"][k])
            for k, s in samplers.items():
                s.load_state_dict(self.state["samplers"][k])
            torch.set_rng_state(self.state["torch_rng"])
            extra.update(self.state["extra"])
        log = self._open_log(phase, ["step", *fields, "wall_s"], start)
        writer = csv.writer(log)
        bar = tqdm(total=total, initial=start, desc=f"{self.name} {phase}",
                   disable=not self.progress)
        sums: dict[str, list[float]] = defaultdict(list)
        done = start

        def position() -> tuple[dict, torch.Tensor]:
            return {k: s.state_dict() for k, s in samplers.items()}, torch.get_rng_state()

        last = position()  # data and RNG position after the last completed step
        try:
            for step in range(start, total):
                for k, v in step_fn(step).items():
                    sums[k].append(v)
                done = step + 1
                last = position()
                bar.update(1)
                if done % tc.log_every == 0 or done == total:
                    means = {k: sum(v) / len(v) for k, v in sums.items() if v}
                    writer.writerow([done, *(_fmt(means.get(f)) for f in fields),
                                     f"{self.wall():.1f}"])
                    log.flush()
                    bar.set_postfix({k: f"{v:.3g}" for k, v in list(means.items())[:4]})
                    sums.clear()
                if on_eval is not None and eval_every and done % eval_every == 0:
                    on_eval(done)
                if done % tc.checkpoint_every == 0 and done < total:
                    self.save(phase, done, optimizers, last[0], extra, last[1])
        except KeyboardInterrupt:  # a step cut short is replayed (its updates may remain)
            self.save(phase, done, optimizers, last[0], extra, last[1])
            raise
        finally:
            bar.close()
            log.close()
        self.state = None

    def _open_log(self, phase: str, header: list[str], start: int):
        path = self.out_dir / f"log_{phase}.csv"
        rows: list[list[str]] = []
        if start > 0 and path.exists():
            with path.open(newline="") as fh:
                rows = [r for r in list(csv.reader(fh))[1:] if r and int(r[0]) <= start]
        fh = path.open("w", newline="")
        csv.writer(fh).writerows([header, *rows])
        fh.flush()
        return fh


def _fmt(v: float | None) -> str:
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return ""
    return f"{v:.5g}"
