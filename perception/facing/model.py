"""The facing network and the estimator the robot loads.

:func:`crop_person` cuts a person box out of a camera frame (grown by ``pad``, letterboxed
to the network's input size); :class:`FacingNet` maps the crop to ``bins`` angle classes;
:class:`FacingEstimator` turns their probabilities into an angle (the circular mean) and a
confidence (the mean resultant length, 1 when every probability sits in one bin). The angle
is the person's facing direction relative to the line from them to the camera: 0 when they
look at the camera, positive when they look to the camera's left of that line (turned
counter-clockwise seen from above), +-pi when they turn their back.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import cv2
import numpy as np
import torch
from torch import nn

from core.checkpoint import atomic_torch_save, fp16_state, fp32_state, read_weights
from core.errors import UserError
from core.torch_threads import torch_threads
from perception.facing.config import CropConfig, FacingModelConfig

Box = tuple[float, float, float, float]


class FacingModelError(UserError):
    """A facing model file is missing or unreadable."""


def crop_person(frame: np.ndarray, box: Box, crop: CropConfig, pad: float) -> np.ndarray:
    """The RGB crop (crop.height, crop.width, 3) of ``box`` (x0, y0, x1, y1 pixels), grown by
    ``pad`` of its size on every side, scaled to fit and centred on a grey letterbox."""
    x0, y0, x1, y1 = box
    w, h = x1 - x0, y1 - y0
    x0, x1 = max(0, int(x0 - pad * w)), min(frame.shape[1], math.ceil(x1 + pad * w) + 1)
    y0, y1 = max(0, int(y0 - pad * h)), min(frame.shape[0], math.ceil(y1 + pad * h) + 1)
    part = frame[y0:y1, x0:x1]
    out = np.full((crop.height, crop.width, 3), 114, np.uint8)
    if part.size == 0:
        return out
    scale = min(crop.width / part.shape[1], crop.height / part.shape[0])
    pw, ph = max(1, round(part.shape[1] * scale)), max(1, round(part.shape[0] * scale))
    resized = cv2.resize(part, (pw, ph), interpolation=cv2.INTER_AREA)
    ox, oy = (crop.width - pw) // 2, (crop.height - ph) // 2
    out[oy:oy + ph, ox:ox + pw] = resized
    return out


def bin_centres(bins: int) -> torch.Tensor:
    """The angle (rad) at the centre of each class, bin 0 at 0."""
    return torch.arange(bins, dtype=torch.float32) * (2 * math.pi / bins)


def angle_bin(angle: float | np.ndarray, bins: int) -> np.ndarray:
    """The class of each angle (rad): the nearest bin centre."""
    return np.round(np.mod(angle, 2 * math.pi) / (2 * math.pi / bins)).astype(np.int64) % bins


class FacingNet(nn.Module):
    """3x3 conv stages with max-pooling, global average pooling, dropout, a linear head."""

    def __init__(self, cfg: FacingModelConfig) -> None:
        super().__init__()
        layers: list[nn.Module] = []
        c_in = 3
        for c in cfg.channels:
            layers += [nn.Conv2d(c_in, c, 3, padding=1, bias=False), nn.BatchNorm2d(c),
                       nn.ReLU(inplace=True), nn.MaxPool2d(2)]
            c_in = c
        self.features = nn.Sequential(*layers)
        self.head = nn.Sequential(nn.AdaptiveAvgPool2d(1), nn.Flatten(), nn.Dropout(cfg.dropout),
                                  nn.Linear(c_in, cfg.bins))

    def forward(self, crops: torch.Tensor) -> torch.Tensor:
        """Logits (N, bins) of uint8 crops (N, 3, H, W)."""
        return self.head(self.features(crops.float() / 127.5 - 1.0))


def to_tensor(crops: np.ndarray) -> torch.Tensor:
    """uint8 crops (N, H, W, 3) as the network's (N, 3, H, W) input."""
    return torch.from_numpy(np.ascontiguousarray(crops)).permute(0, 3, 1, 2)


def circular_mean(probs: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
    """Angle (rad, in (-pi, pi]) and mean resultant length of class probabilities."""
    centres = bin_centres(probs.shape[-1])
    s, c = (probs * centres.sin()).sum(-1), (probs * centres.cos()).sum(-1)
    return torch.atan2(s, c), torch.hypot(s, c)


@dataclass(frozen=True)
class Facing:
    """Where a person looks, relative to the line to the camera (rad), and how sure."""

    angle: float
    confidence: float

    @property
    def view(self) -> str:
        """``front`` (within 45 deg of the camera), ``back`` (past 135 deg) or ``side``."""
        a = abs(math.degrees(self.angle))
        return "front" if a < 45 else "back" if a > 135 else "side"


class FacingEstimator:
    """The trained network with its input settings."""

    def __init__(self, net: FacingNet, crop: CropConfig, pad: float, meta: dict[str, Any]
                 ) -> None:
        self.net, self.crop, self.pad, self.meta = net.eval(), crop, pad, meta

    def save(self, path: Path) -> None:
        """Write the model file (weights in fp16 and the settings) atomically."""
        atomic_torch_save({"weights": fp16_state(self.net), "model": self.meta["model"],
                           "crop": self.crop.model_dump(), "pad": self.pad, "meta": self.meta},
                          path)

    @classmethod
    def load(cls, path: str | Path) -> FacingEstimator:
        """Load a model file written by :meth:`save` (weights only, no code runs)."""
        data = read_weights(path, FacingModelError, "train one: companion train facing")
        try:
            net = FacingNet(FacingModelConfig(**data["model"]))
            net.load_state_dict(fp32_state(data["weights"]))
            return cls(net, CropConfig(**data["crop"]), float(data["pad"]), data["meta"])
        except (KeyError, TypeError, ValueError, RuntimeError) as exc:
            raise FacingModelError(f"{path}: not a facing model file ({exc})") from None

    @torch.no_grad()
    def estimate(self, crops: np.ndarray) -> list[Facing]:
        """The facing of each uint8 crop (N, H, W, 3)."""
        if len(crops) == 0:
            return []
        with torch_threads(1):   # a few crops: one thread beside the simulation is faster
            angle, strength = circular_mean(torch.softmax(self.net(to_tensor(crops)), -1))
        return [Facing(float(a), float(r)) for a, r in zip(angle, strength, strict=True)]

    def facing(self, frame: np.ndarray, box: Box) -> Facing:
        """The facing of the person in ``box`` of the RGB camera ``frame``."""
        return self.estimate(crop_person(frame, box, self.crop, self.pad)[None])[0]
