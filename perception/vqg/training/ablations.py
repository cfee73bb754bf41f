"""The VQG ablations of the thesis (docs/vqg.md): the full model and each ablation trained on a
shortened schedule and scored side by side."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from perception.vqg.config import ABLATIONS, VqgConfig
from perception.vqg.training.evaluate import METRICS, MODEL_FILE, evaluate
from perception.vqg.training.train import IMAGE_FILE, train


def scaled(cfg: VqgConfig, scale: float) -> VqgConfig:
    """``cfg`` with every phase (and the KL warm-up) shortened to ``scale`` of its steps."""
    tc = cfg.train
    update = {k: round(getattr(tc, k) * scale)
              for k in ("image_steps", "vae_steps", "adversarial_steps", "kl_warmup_steps")}
    return cfg.model_copy(update={"train": tc.model_copy(update=update)})


def run_ablations(cfg: VqgConfig, out_root: Path, progress: bool,
                  image_from: Path | None = None) -> list[dict[str, Any]]:
    """Train the full model and each ablation with the same shortened schedule
    (``eval.ablation_scale``) into ``out_root/<name>`` (resumable), evaluate each.

    Without ``image_from`` the full run pre-trains E_I and the ablations reuse it (no
    ablation changes E_I); with it, every run reuses that ``image_encoder.pt``."""

    rows = []
    for name in ("full", *ABLATIONS):
        c = scaled(cfg.ablated(None if name == "full" else name), cfg.eval.ablation_scale)
        out = out_root / name
        train(c, out, resume=(out / "checkpoint.pt").exists(), progress=progress,
              image_from=image_from)
        image_from = image_from or out / IMAGE_FILE
        m = evaluate(out / MODEL_FILE, c, cfg.eval.images, cfg.eval.samples)
        rows.append({"model": name, **{k: m[k] for k in (*METRICS, "bleu", "latency_ms")}})
    return rows


def format_table(rows: list[dict[str, Any]]) -> str:
    """A Markdown table of metric rows."""
    keys = list(rows[0])
    lines = ["| " + " | ".join(keys) + " |", "|" + " --- |" * len(keys)]
    for r in rows:
        lines.append("| " + " | ".join(f"{v:.3f}" if isinstance(v, float) else str(v)
                                       for v in r.values()) + " |")
    return "\n".join(lines)
