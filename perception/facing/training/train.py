"""Training the facing network: one readable loop in the CleanRL manner.

Every hyper-parameter comes from the config (saved as ``resolved_config.yaml``). Each epoch
shuffles the training crops (mirrored at random when ``train.flip``: a mirrored person
looks the other way, so the angle changes sign), takes AdamW steps on the label-smoothed
cross-entropy of the angle bins under a cosine learning-rate schedule, then scores the
validation crops; the best epoch by validation mean angular error is exported. The
checkpoint after every epoch makes an interrupted training resumable (``--resume``): SIGINT
or SIGTERM stops it when the epoch under way ends (:mod:`core.interrupts`).
"""

from __future__ import annotations

import csv
from pathlib import Path
from typing import Any

import numpy as np
import torch
import torch.nn.functional as F  # noqa: N812

from core.checkpoint import TrainingFolder
from core.interrupts import stop_point, stop_requests
from core.torch_threads import torch_threads
from perception.facing.config import FacingConfig
from perception.facing.model import FacingEstimator, FacingModelError, FacingNet, angle_bin
from perception.facing.training.data import load_split
from perception.facing.training.evaluate import facing_metrics

LOG_FIELDS = ["epoch", "train_loss", "val_mae_deg", "val_view_accuracy", "lr", "wall_s"]
MODEL_FILE = "facing.pt"


def _mirror(crops: np.ndarray, angles: np.ndarray, rng: np.random.Generator
            ) -> tuple[np.ndarray, np.ndarray]:
    """Mirror a random half of the crops left-right; their angles change sign."""
    flip = rng.random(len(crops)) < 0.5
    crops = crops.copy()
    crops[flip] = crops[flip][:, :, ::-1]
    return crops, np.where(flip, -angles, angles)


def train(cfg: FacingConfig, data: Path, out: Path, resume: bool = False,
          progress: bool = True) -> dict[str, Any]:
    """Train on the data set in ``data`` into the run folder ``out``; the summary."""
    folder = TrainingFolder(out, resume, FacingModelError)
    folder.use_config(cfg)
    tc = cfg.train
    torch.manual_seed(tc.seed)
    rng = np.random.default_rng(tc.seed)
    tr, va = load_split(data, "train"), load_split(data, "val")
    net = FacingNet(cfg.model)
    opt = torch.optim.AdamW(net.parameters(), lr=tc.lr, weight_decay=tc.weight_decay)
    steps_per_epoch = -(-len(tr["angles"]) // tc.batch)
    sched = torch.optim.lr_scheduler.OneCycleLR(opt, tc.lr, total_steps=tc.epochs * steps_per_epoch,
                                                pct_start=0.15)
    start_epoch, best = 0, float("inf")
    if folder.state is not None:
        folder.restore(net=net, opt=opt, sched=sched)
        rng.bit_generator.state = folder.state["rng"]
        torch.set_rng_state(folder.state["torch_rng"])
        start_epoch, best = folder.state["epoch"], folder.state["best"]
    log = folder.open_log("train_log.csv", LOG_FIELDS, keep=lambda r: int(r[0]) <= start_epoch)
    writer = csv.writer(log)
    with stop_requests(), torch_threads(tc.threads or None), log:
        for epoch in range(start_epoch + 1, tc.epochs + 1):
            stop_point()  # the checkpoint of the epoch before is written
            net.train()
            order = rng.permutation(len(tr["angles"]))
            losses = []
            for i in range(0, len(order), tc.batch):
                idx = order[i:i + tc.batch]
                crops, angles = tr["crops"][idx], tr["angles"][idx]
                if tc.flip:
                    crops, angles = _mirror(crops, angles, rng)
                target = torch.from_numpy(angle_bin(angles, cfg.model.bins))
                logits = net(torch.from_numpy(np.ascontiguousarray(crops)).permute(0, 3, 1, 2))
                loss = F.cross_entropy(logits, target, label_smoothing=tc.label_smoothing)
                opt.zero_grad()
                loss.backward()
                opt.step()
                sched.step()
                losses.append(loss.item())
            estimator = FacingEstimator(net, cfg.data.crop, cfg.data.pad,
                                        {"model": cfg.model.model_dump(), "epoch": epoch})
            net.eval()
            val = facing_metrics(estimator, va)
            if val["mae_deg"] < best:
                best = val["mae_deg"]
                estimator.save(out / MODEL_FILE)
            writer.writerow([epoch, round(float(np.mean(losses)), 5), round(val["mae_deg"], 3),
                             round(val["view_accuracy"], 4), f"{sched.get_last_lr()[0]:.6f}",
                             round(folder.wall(), 1)])
            log.flush()
            folder.save({"net": net.state_dict(), "opt": opt.state_dict(),
                         "sched": sched.state_dict(), "rng": rng.bit_generator.state,
                         "torch_rng": torch.get_rng_state(), "epoch": epoch, "best": best})
            if progress:
                print(f"epoch {epoch}/{tc.epochs}: loss {np.mean(losses):.4f}, "
                      f"val MAE {val['mae_deg']:.1f} deg, view {val['view_accuracy']:.3f}")
    return {"best_val_mae_deg": best, "epochs": tc.epochs, "wall_s": round(folder.wall(), 1),
            "model": str(out / MODEL_FILE)}
