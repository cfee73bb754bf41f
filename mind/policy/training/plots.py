"""Figures in the manner of thesis Figs. 4.2-4.6, saved as PNG."""

from __future__ import annotations

import csv
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from mind.personality import ACTIONS, MOTIVATIONS
from mind.policy.training.env import Trace


def _save(fig: plt.Figure, path: Path) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def training_curves(log_csv: Path, out_dir: Path, window: int = 30) -> list[Path]:
    """Episode reward and secure rate during training, averaged over ``window`` episodes."""
    with log_csv.open() as fh:
        rows = list(csv.DictReader(fh))
    if not rows:
        return []
    ret = np.array([float(r["return"]) for r in rows])
    rsr = np.array([float(r["rsr"]) for r in rows])
    n = len(ret) // window * window or len(ret)
    w = window if len(ret) >= window else len(ret)
    x = np.arange(w, n + 1, w)
    paths = []
    for values, name, label in ((ret, "training_reward.png", "episode reward"),
                                (rsr * 100, "training_rsr.png", "robot secure rate (%)")):
        fig, ax = plt.subplots(figsize=(7, 3.5))
        ax.plot(x, values[:n].reshape(-1, w).mean(axis=1))
        ax.set_xlabel("training episode")
        ax.set_ylabel(f"{label}, mean of {w}")
        ax.grid(alpha=0.3)
        paths.append(_save(fig, out_dir / name))
    return paths


def episode_figures(trace: Trace, mood_threshold: float, out_dir: Path) -> list[Path]:
    """Motivations, the action sequence and the mood value over one test episode."""
    m = np.array(trace.motivations)
    t = np.arange(len(m))
    fig, ax = plt.subplots(figsize=(9, 4))
    for i, name in enumerate(MOTIVATIONS):
        ax.plot(t, m[:, i], label=name, lw=1)
    ax.set_xlabel("step")
    ax.set_ylabel("motivation intensity")
    ax.legend(ncol=3, fontsize=8)
    ax.grid(alpha=0.3)
    paths = [_save(fig, out_dir / "motivations.png")]

    fig, ax = plt.subplots(figsize=(9, 3.5))
    ax.scatter(t, trace.action, s=1, marker="|")
    ax.set_yticks(range(len(ACTIONS)), ACTIONS)
    ax.set_xlabel("step")
    ax.grid(alpha=0.3)
    paths.append(_save(fig, out_dir / "actions.png"))

    fig, ax = plt.subplots(figsize=(9, 3.5))
    ax.plot(t, trace.mood, lw=1, label="mood value")
    ax.axhline(mood_threshold, color="k", ls="--", lw=1, label="threshold (positive below)")
    ax.set_xlabel("step")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    paths.append(_save(fig, out_dir / "mood.png"))
    return paths
