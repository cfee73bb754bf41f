"""The robot's microphones: what a line said in the household becomes for the robot.

Pepper localises a voice with its four-microphone array. Here a :class:`Microphones`
sensor turns each line a person says (:class:`app.sim.world.SayEvent`) into a
:class:`HeardLine`: the words, who they were meant for, and the bearing of the voice as
the array estimates it (the true bearing from the robot's head to the speaker plus
Gaussian noise, ``direction_noise_deg``). The simulator's positions only make the sensor's
reading; the behaviours see the reading alone.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from pydantic import Field

from app.core.config_files import StrictModel
from app.sim.world import SayEvent


class MicrophonesConfig(StrictModel):
    """The microphone array: how far off its bearing of a voice may be."""

    direction_noise_deg: float = Field(ge=0.0, le=180.0)


@dataclass(frozen=True)
class HeardLine:
    """A line the robot heard: ``line`` numbers it within the run; ``bearing`` (rad, world
    frame) is where the voice came from as the microphones localised it; ``promised``:
    the robot told the speaker it would answer later."""

    line: int
    t: float
    person: str
    text: str
    to: str
    bearing: float
    promised: bool = False

    @property
    def to_robot(self) -> bool:
        """Whether the line was meant for the robot (or for everyone)."""
        return self.to in ("robot", "everyone")


class Microphones:
    """Localises voices; one per robot, seeded for reproducible runs."""

    def __init__(self, cfg: MicrophonesConfig, seed: int = 0) -> None:
        self.noise = math.radians(cfg.direction_noise_deg)
        self._rng = np.random.default_rng(seed)
        self._count = 0

    def hear(self, event: SayEvent, listener: tuple[float, float],
             speaker: tuple[float, float]) -> HeardLine:
        """``event`` as heard by a robot standing at ``listener`` (x, y) from a speaker at
        ``speaker`` (x, y)."""
        self._count += 1
        true = math.atan2(speaker[1] - listener[1], speaker[0] - listener[0])
        bearing = true + float(self._rng.normal(0.0, self.noise)) if self.noise else true
        bearing = math.atan2(math.sin(bearing), math.cos(bearing))
        return HeardLine(self._count, event.t, event.person, event.text, event.to, bearing)
