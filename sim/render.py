"""The head camera's renderer: one frame, or one band of rows of a frame, from PyBullet's
TinyRenderer (:class:`sim.split_render.SplitRenderer` shares the bands of each frame
between the run and a helper process)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
import pybullet as p

Buffers = tuple[np.ndarray, np.ndarray, np.ndarray]   # RGBA (h, w, 4), depth, segmentation


def tiny_render(client: int, width: int, height: int, view: Sequence[float],
                proj: Sequence[float], flags: int, light: dict[str, Any]) -> Buffers:
    """One frame from PyBullet's TinyRenderer in ``client``: RGBA, the OpenGL depth
    buffer and the segmentation mask, each (height, width)."""
    _, _, rgba, zbuf, seg = p.getCameraImage(width, height, view, proj, flags=flags,
                                             renderer=p.ER_TINY_RENDERER,
                                             physicsClientId=client, **light)
    return (np.asarray(rgba, dtype=np.uint8).reshape(height, width, 4),
            np.asarray(zbuf, dtype=np.float32).reshape(height, width),
            np.asarray(seg, dtype=np.int32).reshape(height, width))


def band_projection(proj: Sequence[float], height: int, row0: int, row1: int) -> list[float]:
    """``proj`` (OpenGL, column-major) narrowed to image rows ``[row0, row1)`` of a frame
    ``height`` rows high (row 0 at the top): those rows' span of normalised device y is
    stretched to the whole of [-1, 1]."""
    top, bottom = 1 - 2 * row0 / height, 1 - 2 * row1 / height
    band = np.eye(4)
    band[1, 1] = 2 / (top - bottom)
    band[1, 3] = -(top + bottom) / (top - bottom)
    matrix = np.asarray(proj, dtype=np.float64).reshape(4, 4).T
    return (band @ matrix).T.reshape(-1).tolist()
