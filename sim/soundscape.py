"""The background sounds of a household as loops at the microphones' rate: steady noise
(ventilation, traffic, the robot's fans: pink noise, whose power falls 3 dB an octave like
most room noise) and a programme playing from a TV or radio (a presenter's voice over a
bed of noise), each scaled to unit RMS; sim/acoustics.py sets their levels."""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from robot.audio import RATE, resampled
from robot.voices import Voice, synthesise

LOOP_S = 20.0   # seconds of each loop
PRESENTER = Voice(name="en-GB-x-rp", variant="m2", pitch=45, speed=165)
PROGRAMME = (
    "Good evening, here are the headlines at this hour.",
    "Heavy rain is expected across the north tonight, with strong winds by the coast.",
    "The city council has approved the plan for a new bridge over the river.",
    "In football, the home side won their third match in a row on Saturday.",
    "Prices in the shops rose slightly last month, the figures show.",
    "Scientists say the spring was the warmest since records began.",
    "And finally, a lost dog has found its way home after a journey of forty miles.",
)


def unit(x: np.ndarray) -> np.ndarray:
    """``x`` scaled to unit RMS."""
    return x / max(float(np.sqrt((x ** 2).mean())), 1e-12)


def pink_noise(seconds: float, seed: int) -> np.ndarray:
    """Pink noise at the microphones' rate, unit RMS (white noise shaped by 1/sqrt(f))."""
    n = int(seconds * RATE)
    spectrum = np.fft.rfft(np.random.default_rng(seed).normal(size=n))
    f = np.fft.rfftfreq(n, 1.0 / RATE)
    spectrum[1:] /= np.sqrt(f[1:] / f[1])
    spectrum[0] = 0.0
    return unit(np.fft.irfft(spectrum, n))


@lru_cache(maxsize=2)
def noise_loops(seed: int) -> dict[str, np.ndarray]:
    """The loops by kind (``steady``, ``programme``), made once per process and seed."""
    speech = []
    for sentence in PROGRAMME:
        samples, rate = synthesise(sentence, PRESENTER)
        speech.append(resampled(samples, rate))
        speech.append(np.zeros(int(0.25 * RATE)))
    voice = np.resize(unit(np.concatenate(speech)), int(LOOP_S * RATE))
    programme = unit(voice + 0.3 * pink_noise(LOOP_S, seed + 1))
    return {"steady": pink_noise(LOOP_S, seed), "programme": programme}
