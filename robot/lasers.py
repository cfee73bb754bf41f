"""The robot's base laser scanners as it knows them: where they sit and how far they
reach (robot.yaml ``lasers``), and what one reading of them holds (:class:`Scan`).
``sim/lasers.py`` casts the simulated rays."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Self

import numpy as np
from pydantic import Field, PositiveFloat, PositiveInt, model_validator

from core.config_files import StrictModel


class LasersConfig(StrictModel):
    """Pepper's base scanners: where they sit, how many rays each casts, how far they reach."""

    height_m: PositiveFloat
    rays: PositiveInt
    fov_deg: float = Field(gt=0.0, lt=180.0)
    range_min_m: float = Field(ge=0.0)
    range_max_m: PositiveFloat
    mount_radius_m: float = Field(ge=0.0)
    scanners: dict[str, float] = Field(min_length=1)   # name -> facing (deg, 0 = forwards)

    @model_validator(mode="after")
    def _ranges(self) -> Self:
        if self.range_min_m >= self.range_max_m:
            raise ValueError("need range_min_m < range_max_m")
        return self


@dataclass(frozen=True)
class Scan:
    """One reading of every ray, in the world frame: where each ray starts (``origins``,
    (N, 2) m), where it ended (``ends``), and whether it ended on a surface (``hit``) rather
    than at its maximum range or on the robot itself."""

    origins: np.ndarray
    ends: np.ndarray
    hit: np.ndarray

    @property
    def points(self) -> np.ndarray:
        """The (M, 2) points where rays met a surface."""
        return self.ends[self.hit]
