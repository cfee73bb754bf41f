"""Learning curves of ``companion eval feedback``: time on disliked and liked actions
against the feedback a user has given, per user type, with and without adaptation."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from core.checkpoint import atomic_write
from mind.preferences.evaluation.evaluate import BIN


def learning_curves(summary: dict[str, Any], out: Path) -> Path:
    """``learning_curves.png``: one panel per user type, a line per arm and taste."""
    out.mkdir(parents=True, exist_ok=True)
    arms = summary["arms"]
    curves = next(iter(arms.values()))["curves"]
    kinds = sorted(k for k, c in curves.items()   # users with no taste have nothing to show
                   if any(v for taste in c.values() for v in taste))
    fig, axes = plt.subplots(1, len(kinds), figsize=(4 * len(kinds), 3.4), sharey=True,
                             squeeze=False)
    for ax, kind in zip(axes[0], kinds, strict=True):
        for i, (mode, row) in enumerate(arms.items()):
            for taste, style in (("disliked", "-"), ("liked", "--")):
                values = row["curves"][kind][taste]
                x = [k * BIN for k, v in enumerate(values) if v is not None]
                y = [v for v in values if v is not None]
                if any(y):
                    ax.plot(x, y, style, color=f"C{i}", label=f"{mode}: {taste}")
        ax.set_title(kind.replace("_", " "))
        ax.set_xlabel("feedback events the user has given")
    axes[0][0].set_ylabel("share of the robot's time")
    axes[0][-1].legend(fontsize=7)
    fig.tight_layout()
    path = out / "learning_curves.png"
    atomic_write(path, lambda fh: fig.savefig(fh, dpi=90, format="png"))
    plt.close(fig)
    return path
