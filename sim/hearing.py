"""The robot's microphones: what a line said in the household becomes for the robot.

Pepper localises a voice with its four-microphone array. Here :class:`Microphones` turns
each line a person says (:class:`robot.percepts.SayEvent`, or words of encouragement) into a
:class:`Sound`: what the microphones record while it is said (the voice carried through the
household by :mod:`sim.acoustics`, over the background of the robot's room), with where
the head faced. A line too faint to rise above the noise makes no sound at all. With
``array`` the sound holds each of the head's four microphones (``(4, n)``,
:meth:`Acoustics.parts_at_array`), and the robot places the voice itself from them; with one
microphone, which cannot place it, the sound carries a stand-in bearing (the true bearing
from the robot's head to the speaker plus Gaussian noise, ``direction_noise_deg``). The
words themselves are not
in a :class:`Sound`: the robot gets them only by recognising the recording
(``dialogue/speech``). The simulator's positions only make the recording; the behaviours
see the recording alone.

Who said a line, and to whom, are still given (docs/what_the_robot_is_given.md).
"""

from __future__ import annotations

import math

import numpy as np
from pydantic import Field

from core.config_files import StrictModel


class MicrophonesConfig(StrictModel):
    """The microphone array: how far off its bearing of a voice may be, and how far below
    the background a voice may be and still make a sound worth recognising."""

    direction_noise_deg: float = Field(ge=0.0, le=180.0)
    audible_below_noise_db: float = Field(ge=0.0, le=40.0)
    array: bool     # record each head microphone (Acoustics.parts_at_array), not one


class Microphones:
    """Numbers the lines and, for one microphone's recordings, stands in for a localiser;
    one per robot, seeded for reproducible runs."""

    def __init__(self, cfg: MicrophonesConfig, seed: int = 0) -> None:
        self.cfg = cfg
        self.noise = math.radians(cfg.direction_noise_deg)
        self.rng = np.random.default_rng(seed)
        self._count = 0

    def number(self) -> int:
        """The next line's number (lines are numbered whether heard or not)."""
        self._count += 1
        return self._count

    def bearing(self, listener: tuple[float, float], speaker: tuple[float, float]) -> float:
        """The bearing of a voice at ``speaker`` heard at ``listener``, as localised."""
        true = math.atan2(speaker[1] - listener[1], speaker[0] - listener[0])
        bearing = true + float(self.rng.normal(0.0, self.noise)) if self.noise else true
        return math.atan2(math.sin(bearing), math.cos(bearing))
