"""How well the facing model reads where people look, on held-out rendered crops.

* ``mae_deg``: mean absolute angular error between the estimate and the true facing angle;
* ``view_accuracy``: share whose view (front within 45 deg of the camera, back past 135 deg,
  side in between) is the true one;
* the same two by pose (standing, sitting, arms raised) and the share of crops with an error
  above 90 deg (the robot would go to the wrong side of them).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from perception.facing.model import Facing, FacingEstimator
from perception.facing.training.data import POSE_IDS

BATCH = 512


def _views(angles: np.ndarray) -> np.ndarray:
    a = np.degrees(np.abs(angles))
    return np.where(a < 45, 0, np.where(a > 135, 2, 1))


def facing_metrics(estimator: FacingEstimator, split: dict[str, np.ndarray]) -> dict[str, Any]:
    """The metrics of the module docstring on one split."""
    crops, truth = split["crops"], split["angles"].astype(np.float64)
    found: list[Facing] = []
    for i in range(0, len(crops), BATCH):
        found += estimator.estimate(crops[i:i + BATCH])
    est = np.array([f.angle for f in found])
    err = np.degrees(np.abs(np.remainder(est - truth + math.pi, 2 * math.pi) - math.pi))
    right = _views(est) == _views(truth)
    out: dict[str, Any] = {"crops": len(truth), "mae_deg": float(err.mean()) if len(err) else 0.0,
                           "view_accuracy": float(right.mean()) if len(err) else 0.0,
                           "wrong_side_share": float((err > 90).mean()) if len(err) else 0.0}
    poses = split.get("poses")
    if poses is not None:
        out["by_pose"] = {name: {"crops": int((poses == k).sum()),
                                 "mae_deg": float(err[poses == k].mean()),
                                 "view_accuracy": float(right[poses == k].mean())}
                          for k, name in enumerate(POSE_IDS) if (poses == k).any()}
    return out


HIGHER_IS_BETTER = ("view_accuracy",)


def bars_met(result: dict[str, Any], bars: dict[str, float]) -> dict[str, bool]:
    """Each bar of ``bars`` against ``result``: at least the bar for the accuracies, at most
    it for the errors."""
    return {k: result[k] >= v if k in HIGHER_IS_BETTER else result[k] <= v
            for k, v in bars.items()}
