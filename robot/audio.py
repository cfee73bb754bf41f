"""The robot's microphones as a recorder: their sample rate, their gain, bringing audio of
another rate to theirs, and the speed of sound its array processing assumes."""

from __future__ import annotations

import math

import numpy as np
from scipy.signal import resample_poly

RATE = 16_000             # Hz: the microphones' rate (what speech recognition takes)
REFERENCE_DB = 100.0      # dB SPL of a full-scale (RMS 32,768) signal: the microphones' gain
SPEED_OF_SOUND = 343.0    # m/s in a room at 20 degrees C


def resampled(samples: np.ndarray, rate: int) -> np.ndarray:
    """Mono ``samples`` at ``rate`` as floats at the microphones' rate."""
    x = np.asarray(samples, dtype=np.float64)
    g = math.gcd(RATE, rate)
    return x if rate == RATE else resample_poly(x, RATE // g, rate // g)
