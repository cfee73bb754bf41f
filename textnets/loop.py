"""The training loop shared by the adversarial text models (style transfer, VQG): phases of
steps with checkpoints, CSV logs, progress and resume.

One ``checkpoint.pt`` holds the weights of all networks, the finished phases and, for the
phase under way, its step, optimizers, batch samplers, RNG state and extra values. It is
written atomically every ``checkpoint_every`` steps, at the end of each phase and on Ctrl-C;
``--resume`` continues from it. Each phase appends to ``log_<phase>.csv`` (means over
``log_every`` steps, flushed at once); on resume, rows past the checkpoint are dropped. The
folder, checkpoint file and logs are :class:`core.checkpoint.TrainingFolder`'s.
"""

from __future__ import annotations

import csv
import math
from collections import defaultdict
from collections.abc import Callable
from pathlib import Path
from typing import Generic, Protocol, TypeVar

import torch
from torch import nn
from tqdm import tqdm

from core.checkpoint import TrainingFolder
from core.errors import UserError
from textnets.batch import BatchSampler

StepFn = Callable[[int], dict[str, float]]


class LoopSettings(Protocol):
    """How often the loop logs and checkpoints (a config's ``train`` section)."""

    log_every: int
    checkpoint_every: int


class TrainingConfig(Protocol):
    """A model's whole training config; the loop reads its ``train`` section only."""

    @property
    def train(self) -> LoopSettings:
        """The loop's settings."""
        ...


C = TypeVar("C", bound=TrainingConfig)


class Run(Generic[C]):
    """A training run of ``nets`` configured by ``cfg`` (see the module docstring)."""

    def __init__(self, cfg: C, out_dir: Path, nets: dict[str, nn.Module],
                 resume: bool, progress: bool, name: str = "style") -> None:
        self.cfg, self.out_dir, self.nets, self.progress = cfg, out_dir, nets, progress
        self.name = name  # shown on the progress bars
        self.folder = TrainingFolder(out_dir, resume)
        self.ckpt_path = self.folder.ckpt_path
        self.state = self.folder.state
        self.done: list[str] = []
        if self.state is not None:
            self._load_nets()
            self.done = list(self.state["done"])

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
        return self.folder.wall()

    def save(self, phase: str | None, step: int = 0, optimizers: dict | None = None,
             samplers: dict | None = None, extra: dict | None = None,
             rng: torch.Tensor | None = None, sums: dict | None = None) -> None:
        """Write the checkpoint atomically (``samplers`` maps names to their states; ``sums``
        holds the values logged since the last log row, so that a resumed run's next row
        averages the same steps as an uninterrupted one's)."""
        self.folder.save({
            "sums": sums or {},
            "nets": {k: v.state_dict() for k, v in self.nets.items()}, "done": self.done,
            "phase": phase, "step": step,
            "optimizers": {k: v.state_dict() for k, v in (optimizers or {}).items()},
            "samplers": samplers or {},
            "torch_rng": torch.get_rng_state() if rng is None else rng,
            "extra": extra or {},
        })

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
        sums: dict[str, list[float]] = defaultdict(list)
        if self.state is not None and self.state["phase"] == phase:
            sums.update({k: list(v) for k, v in self.state.get("sums", {}).items()})
        log = self.folder.open_log(f"log_{phase}.csv", ["step", *fields, "wall_s"],
                                   keep=lambda row: int(row[0]) <= start)
        writer = csv.writer(log)
        bar = tqdm(total=total, initial=start, desc=f"{self.name} {phase}",
                   disable=None if self.progress else True)  # None: no bar off a terminal
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
                    self.save(phase, done, optimizers, last[0], extra, last[1], dict(sums))
        except KeyboardInterrupt:  # a step cut short is replayed (its updates may remain)
            self.save(phase, done, optimizers, last[0], extra, last[1], dict(sums))
            raise
        finally:
            bar.close()
            log.close()
        self.state = None


def _fmt(v: float | None) -> str:
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return ""
    return f"{v:.5g}"
