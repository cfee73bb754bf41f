"""Training the voice enhancer (:mod:`dialogue.speech.enhancer`).

The loop, in the open: make the sounds (:mod:`.enhancer_data`), hold a share out for
validation, then for each epoch take random crops of the training sounds in batches, mask
the recording's spectrum and compare its magnitudes with the voice's, both raised to
``compression`` (loud and quiet cells count more evenly; Wilson et al., 2018, "Exploring
tradeoffs in models for low-latency speech enhancement"). After each epoch the model with
the lowest validation loss so far is written, atomically, with every hyper-parameter, so
an interrupted run keeps its best model. With ``init`` the network starts from a trained
enhancer's weights instead of random ones (to teach it another rendering of the rooms).
"""

from __future__ import annotations

import json
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np
import torch

from core.checkpoint import (
    atomic_torch_save,
    atomic_write_bytes,
    fp16_state,
    fp32_state,
    read_weights,
)
from core.paths import from_root
from dialogue.speech.config import EnhancerTrainConfig, SpeechModelError
from dialogue.speech.enhancer import BINS, MaskNet
from dialogue.speech.training.enhancer_data import Examples, make_examples


def _crop(examples: Examples, index: list[int], frames: int, rng: np.random.Generator
          ) -> tuple[torch.Tensor, torch.Tensor]:
    """A batch of ``frames``-long crops (sounds shorter than that are repeated)."""
    mixed, voice = [], []
    for i in index:
        m, v = examples.mixed[i].float(), examples.voice[i].float()
        if len(m) < frames:
            reps = -(-frames // len(m))
            m, v = m.repeat(reps, 1), v.repeat(reps, 1)
        start = int(rng.integers(len(m) - frames + 1))
        mixed.append(m[start:start + frames])
        voice.append(v[start:start + frames])
    return torch.stack(mixed), torch.stack(voice)


def spectral_loss(net: MaskNet, mixed: torch.Tensor, voice: torch.Tensor, power: float
                  ) -> torch.Tensor:
    """Mean squared difference of the masked recording's and the voice's magnitudes, each
    raised to ``power``; both given as log power (``log(|X|^2 + 1)``)."""
    magnitude = torch.expm1(mixed).clamp_min(0.0).pow(power / 2)
    target = torch.expm1(voice).clamp_min(0.0).pow(power / 2)
    return (net(mixed) * magnitude - target).square().mean()


def _validation_loss(net: MaskNet, examples: Examples, index: list[int], power: float
                     ) -> float:
    with torch.no_grad():
        losses = [spectral_loss(net, examples.mixed[i].float()[None],
                                examples.voice[i].float()[None], power).item() for i in index]
    return float(np.mean(losses))


def train_enhancer(cfg: EnhancerTrainConfig, lines: list[list[str]], out_dir: Path,
                   progress: Callable[[str], None] | None = None) -> dict[str, object]:
    """Train on ``lines`` (spoken words of training lines) and write ``out_dir/enhancer.pt``
    and its training log ``enhancer.json``; the figures."""
    say = progress or (lambda _: None)
    torch.manual_seed(cfg.seed)
    torch.set_num_threads(cfg.threads)
    rng = np.random.default_rng(cfg.seed)
    t0 = time.perf_counter()
    examples = make_examples(lines, cfg, say)
    order = rng.permutation(len(examples.mixed)).tolist()
    n_val = max(1, int(cfg.validation_share * len(order)))
    val, train = order[:n_val], order[n_val:]
    net = MaskNet(cfg.hidden, cfg.layers)
    if cfg.init is None:
        features = torch.cat([examples.mixed[i].float() for i in train[:500]])
        net.scale.copy_(torch.stack([features.mean(0), features.std(0)]))
    else:   # go on from a trained enhancer of the same size (its features' scale too)
        net.load_state_dict(fp32_state(read_weights(
            from_root(cfg.init), SpeechModelError, "enhance.init names it")["state_dict"]))
    optimiser = torch.optim.Adam(net.parameters(), lr=cfg.learning_rate)
    steps = cfg.epochs * (len(train) // cfg.batch)
    schedule = torch.optim.lr_scheduler.OneCycleLR(optimiser, cfg.learning_rate, total_steps=steps)
    out_dir.mkdir(parents=True, exist_ok=True)
    log: list[dict[str, float]] = []
    best = float("inf")
    for epoch in range(cfg.epochs):
        net.train()
        shuffled = rng.permutation(train).tolist()
        losses = []
        for b in range(len(train) // cfg.batch):
            mixed, voice = _crop(examples, shuffled[b * cfg.batch:(b + 1) * cfg.batch],
                                 cfg.crop_frames, rng)
            loss = spectral_loss(net, mixed, voice, cfg.compression)
            optimiser.zero_grad()
            loss.backward()
            torch.nn.utils.clip_grad_norm_(net.parameters(), cfg.max_grad_norm)
            optimiser.step()
            schedule.step()
            losses.append(loss.item())
        net.eval()
        row = {"epoch": epoch + 1, "train_loss": round(float(np.mean(losses)), 5),
               "validation_loss": round(_validation_loss(net, examples, val, cfg.compression), 5),
               "minutes": round((time.perf_counter() - t0) / 60, 1)}
        log.append(row)
        say(json.dumps(row))
        if row["validation_loss"] < best:
            best = row["validation_loss"]
            atomic_torch_save({"state_dict": fp16_state(net),
                               "hyperparameters": cfg.model_dump(mode="json")},
                              out_dir / "enhancer.pt")
    figures = {"examples": len(examples.mixed), "validation": n_val, "bins": BINS,
               "parameters": sum(p.numel() for p in net.parameters()),
               "best_validation_loss": best, "log": log}
    atomic_write_bytes(out_dir / "enhancer.json", (json.dumps(figures, indent=2) + "\n").encode())
    return figures
