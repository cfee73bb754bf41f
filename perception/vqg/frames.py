"""A camera frame as the VQG networks' input: resized to the model's input size, channels first."""

from __future__ import annotations

import cv2
import numpy as np
import torch


def prepare_frame(rgb: np.ndarray, width: int, height: int) -> torch.Tensor:
    """An RGB ``(H, W, 3)`` uint8 frame as the model's ``(3, height, width)`` uint8 input."""
    if rgb.ndim != 3 or rgb.shape[2] != 3:
        raise ValueError(f"expected an RGB frame (H, W, 3), got shape {rgb.shape}")
    small = cv2.resize(np.ascontiguousarray(rgb[..., :3], dtype=np.uint8), (width, height),
                       interpolation=cv2.INTER_AREA)
    return torch.from_numpy(small).permute(2, 0, 1).contiguous()
