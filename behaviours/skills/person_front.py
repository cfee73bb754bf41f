"""Which way the person find people follows faces, from the facing model's readings of
their box (Sense reads them: ``facings``).

Each confident reading of the person's box (``facing_min_confidence``) within
``facing_max_distance_m`` is turned into a world direction (the bearing from them to the
robot plus the read angle) and added as a unit vector; their front is the mean direction,
trusted for a detour round to it once ``facing_frames`` readings agree enough to sum
(docs/find_people.md).
"""

from __future__ import annotations

import math

from behaviours.config import FindPeopleConfig
from perception.facing.model import Facing


class PersonFront:
    """The summed facing readings of one followed person."""

    def __init__(self, cfg: FindPeopleConfig) -> None:
        self.cfg = cfg
        self._sum, self._frames = (0.0, 0.0), 0

    def forget(self) -> None:
        """Start afresh (another person, or a new place to read them from)."""
        self._sum, self._frames = (0.0, 0.0), 0

    def guess(self) -> float | None:
        """The mean of the readings so far (world direction, rad), or None."""
        return math.atan2(self._sum[1], self._sum[0]) if self._frames else None

    def read(self, seen: Facing | None, spot: tuple[float, float] | None,
             dist: float | None, robot: tuple[float, float]) -> tuple[float, float] | None:
        """Add this frame's reading ``seen`` of the person (standing at ``spot``, ``dist``
        away from the robot at ``robot``); their front and how far (rad) it is from looking
        at the robot, once ``facing_frames`` confident readings are in; else None."""
        cfg = self.cfg
        if seen is None or dist is None or spot is None or dist > cfg.front.max_distance_m:
            return None
        to_robot = math.atan2(robot[1] - spot[1], robot[0] - spot[0])
        if seen.confidence >= cfg.front.min_confidence:
            world = to_robot + seen.angle
            self._sum = (self._sum[0] + math.cos(world), self._sum[1] + math.sin(world))
            self._frames += 1
        front = self.guess()
        if front is None or self._frames < cfg.front.frames:
            return None
        return front, abs(math.remainder(front - to_robot, math.tau))
