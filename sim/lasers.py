"""The robot's base laser scanners: three fans of horizontal rays a little above the floor.

Pepper carries three laser scanners in its base, looking forwards, to the left and to the
right, each a fan of rays a few centimetres above the floor. :class:`LaserScanners` casts
the same fans as PyBullet rays (one ``rayTestBatch`` for all of them) from the base's
shell, at the base's pose now, and reports where each ray ended: on a surface (a hit) or
at its maximum range. A ray that meets the robot's own body is cut there and counts as no
return: the robot never sees itself. People are kinematic bodies that make no contacts,
but rays find them like any other body (docs/navigation.md).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import pybullet as p

from robot.lasers import LasersConfig, Scan

Pose = tuple[float, float, float]


class LaserScanners:
    """The scanners of the robot whose base body is ``body``, posed by ``pose()``."""

    def __init__(self, client: int, body: int, cfg: LasersConfig,
                 pose: Callable[[], Pose]) -> None:
        self.client, self.body, self.cfg, self._pose = client, body, cfg, pose
        half = math.radians(cfg.fov_deg) / 2
        fan = np.linspace(-half, half, cfg.rays) if cfg.rays > 1 else np.zeros(1)
        facings = np.radians(list(cfg.scanners.values()))
        #: each ray's direction relative to the robot's heading, and its scanner's facing
        self.angles = (facings[:, None] + fan[None, :]).ravel()
        self.mounts = np.repeat(facings, cfg.rays)

    @property
    def names(self) -> tuple[str, ...]:
        """The scanners, in the order of the rays (``rays`` each)."""
        return tuple(self.cfg.scanners)

    def scan(self) -> Scan:
        """Cast every ray from the robot's pose now."""
        cfg = self.cfg
        x, y, yaw = self._pose()
        mounts = yaw + self.mounts
        base = np.stack([x + cfg.mount_radius_m * np.cos(mounts),
                         y + cfg.mount_radius_m * np.sin(mounts)], axis=1)
        heading = yaw + self.angles
        unit = np.stack([np.cos(heading), np.sin(heading)], axis=1)
        origins = base + cfg.range_min_m * unit
        far = base + cfg.range_max_m * unit
        z = np.full((len(unit), 1), cfg.height_m)
        results = p.rayTestBatch(np.hstack([origins, z]).tolist(), np.hstack([far, z]).tolist(),
                                 physicsClientId=self.client)
        fraction = np.array([r[2] for r in results])
        body = np.array([r[0] for r in results])
        hit = (body >= 0) & (body != self.body)
        ends = origins + fraction[:, None] * (far - origins)
        return Scan(origins, ends, hit)
