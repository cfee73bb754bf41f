"""The robot's head microphones as an array: how one sound differs from one microphone to
the next (docs/acoustics.md, *Four microphones*).

A source metres away reaches a head a few centimetres across as a plane wave: each
microphone hears it delayed by the projection of its position on the source's direction,
over the speed of sound. Reverberation and room noise arrive from every direction at once
(a diffuse field). In such a field two microphones ``d`` apart are correlated by
``sinc(2 f d / c)`` at frequency ``f`` (Cook et al., 1955, the spherically isotropic
field): fully at low frequencies, hardly above ``c / 2d``. Independent signals, one per
microphone, are given that coherence by mixing them at each frequency of their short-time
spectra with a Cholesky factor of the coherence matrix (Habets and Gannot, 2007,
"Generating sensor signals in isotropic noise fields"). The microphones' own noise is
independent at each.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from scipy.signal import istft, stft

from robot.audio import SPEED_OF_SOUND

N_FFT = 512              # the mixing's frames: 32 ms at 16 kHz
Point = tuple[float, float]


class MicrophoneArray:
    """Microphones at ``positions`` (m in the head's frame: x forwards, y to the left)
    recording at ``rate`` Hz."""

    def __init__(self, positions: Sequence[Point], rate: int) -> None:
        self.positions = np.asarray(positions, dtype=np.float64)
        self.rate = rate
        spacing = np.linalg.norm(self.positions[:, None] - self.positions[None], axis=-1)
        freqs = np.fft.rfftfreq(N_FFT, 1.0 / rate)
        coherence = np.sinc(2.0 * freqs[:, None, None] * spacing[None] / SPEED_OF_SOUND)
        eye = np.eye(len(self.positions))
        self._mixing = np.linalg.cholesky(coherence + 1e-6 * eye)   # (bins, M, M)

    @property
    def count(self) -> int:
        """How many microphones."""
        return len(self.positions)

    def delays(self, source: Point, head: Point, heading: float) -> np.ndarray:
        """Each microphone's delay (s) behind the head's centre for a source at ``source``,
        the head at ``head`` facing ``heading`` (rad, world frame)."""
        towards = np.subtract(source, head)
        towards /= max(float(np.linalg.norm(towards)), 1e-9)
        c, s = math.cos(heading), math.sin(heading)
        world = self.positions @ np.array([[c, s], [-s, c]])
        return -(world @ towards) / SPEED_OF_SOUND

    def delayed(self, x: np.ndarray, delays: np.ndarray) -> np.ndarray:
        """``x`` as each microphone hears it (``(M, len(x))``): shifted by ``delays`` (s),
        fractions of a sample included (a phase ramp over the whole sound's spectrum)."""
        n = len(x)
        size = 1 << (n + 2 * int(np.abs(delays).max() * self.rate + 2)).bit_length()
        freqs = np.fft.rfftfreq(size, 1.0 / self.rate)
        spectrum = np.fft.rfft(x, size)[None] * np.exp(-2j * np.pi * freqs[None] * delays[:, None])
        return np.fft.irfft(spectrum, size)[:, :n]

    def diffuse(self, independent: np.ndarray) -> np.ndarray:
        """``independent`` signals (``(M, n)``, one per microphone, equally loud) mixed so
        that each pair is as correlated as in a diffuse field; the same loudness."""
        n = independent.shape[1]
        _, _, spectra = stft(independent, nperseg=N_FFT, noverlap=N_FFT // 2)
        mixed = np.einsum("fij,jft->ift", self._mixing, spectra)
        return istft(mixed, nperseg=N_FFT, noverlap=N_FFT // 2)[1][:, :n]
