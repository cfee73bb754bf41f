"""Reading a user's WAV file for the recogniser: 16-bit PCM, mono or several channels (the
head's microphones, as a household run with audio writes them)."""

from __future__ import annotations

import io
import wave
from pathlib import Path

import numpy as np

from core.errors import UserError
from core.files import read_bytes

WAV_LIMIT = 64 << 20      # bytes: about 30 minutes of 16 kHz 16-bit audio
MIN_RATE, MAX_RATE = 8_000, 96_000


class WavError(UserError):
    """A WAV file the recogniser cannot take."""


def read_wav(path: Path, all_channels: bool = False) -> tuple[np.ndarray, int]:
    """The samples (int16: the first channel, or with ``all_channels`` every one as a row
    of ``(channels, n)``) and rate of the WAV file at ``path``."""
    data = read_bytes(path, WAV_LIMIT)
    try:
        with wave.open(io.BytesIO(data), "rb") as w:
            width, channels, rate = w.getsampwidth(), w.getnchannels(), w.getframerate()
            frames = w.readframes(w.getnframes())
    except (wave.Error, EOFError) as exc:
        raise WavError(f"{path}: not a WAV file the recogniser can read ({exc})") from None
    if width != 2:
        raise WavError(f"{path}: {8 * width}-bit samples; the recogniser takes 16-bit PCM")
    if not MIN_RATE <= rate <= MAX_RATE:
        raise WavError(f"{path}: a rate of {rate} Hz; give {MIN_RATE}-{MAX_RATE} Hz")
    samples = np.frombuffer(frames, dtype="<i2").reshape(-1, channels).T
    if samples.shape[1] == 0:
        raise WavError(f"{path}: no samples")
    return (samples if all_channels else samples[0]).copy(), rate
