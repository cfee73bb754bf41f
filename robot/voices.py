"""Voices: the robot's and each person's, synthesised in this process by espeak-ng.

The espeak-ng library and its voice data come inside the ``espeakng-loader`` wheel, so
speech needs nothing from the system. The library is called through ctypes, in its
synchronous mode: each sentence comes back through a callback as 16-bit samples (22,050 Hz),
and :func:`synthesise` returns them as one array. espeak-ng keeps one global state per
process, and some of it runs on from one sentence to the next where its API cannot reset it
(the same line said twice in a row came out different), so the library is loaded, started,
and unloaded again for each sentence (about a millisecond): a line sounds the same whatever
the process said before it, so runs, tests and training sounds do not depend on their order.

A :class:`Voice` names an espeak-ng voice (a language and accent such as ``en-us``,
``en``, ``en-GB-scotland`` or ``en-029``), an optional variant (``f1``-``f5`` female, ``m1``-
``m7`` male, ...), a pitch (0-99) and a speed (words a minute).
"""

from __future__ import annotations

import _ctypes
import ctypes
import io
import threading
import wave
from typing import Any

import espeakng_loader
import numpy as np
from pydantic import Field, field_validator

from core.config_files import StrictModel

SYNCHRONOUS = 2          # espeak_AUDIO_OUTPUT: samples handed to the callback as they come
POSITION_CHARACTER = 1   # espeak_POSITION_TYPE
CHARS_UTF8 = 1           # espeak_Synth flags
RATE, PITCH = 1, 3       # espeak_PARAMETER
SEED = 1                 # of espeak-ng's noise (breathy voices), set before each line
_CALLBACK = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.POINTER(ctypes.c_short), ctypes.c_int,
                             ctypes.c_void_p)


class VoiceError(ValueError):
    """A voice espeak-ng does not have, or a sentence it could not say."""


class Voice(StrictModel):
    """An espeak-ng voice: ``name`` (language and accent), ``variant``, ``pitch`` (0-99)
    and ``speed`` (words a minute)."""

    name: str = Field(default="en-us", min_length=1, max_length=40)
    variant: str | None = Field(default=None, min_length=1, max_length=20)
    pitch: int = Field(default=50, ge=0, le=99)
    speed: int = Field(default=150, ge=80, le=450)

    @field_validator("name", "variant")
    @classmethod
    def _plain(cls, value: str | None) -> str | None:
        if value is not None and not value.replace("-", "").replace("_", "").isalnum():
            raise ValueError("letters, digits, '-' and '_' only")
        return value

    @property
    def espeak_name(self) -> str:
        """The name espeak-ng selects it by: ``name`` or ``name+variant``."""
        return self.name if self.variant is None else f"{self.name}+{self.variant}"


# Voices people get when their scenario gives none, in the order they are listed: different
# voicings and pitches, so that each person of a household sounds like themselves, all in
# General American at an unhurried pace: the ones the robot's speech recogniser hears best of
# espeak-ng's (docs/speech.md; the British, Scottish and Caribbean accents and the faster
# voices first tried here more than doubled its word error rate).
PEOPLE_VOICES = (
    Voice(name="en-us", variant="klatt4", pitch=52, speed=130),
    Voice(name="en-us", variant="f5", pitch=70, speed=125),
    Voice(name="en-us", variant="f2", pitch=60, speed=135),
    Voice(name="en-us", variant="klatt3", pitch=42, speed=130),
    Voice(name="en-us", variant="klatt", pitch=50, speed=140),
    Voice(name="en-us", variant="klatt2", pitch=38, speed=125),
)


class _Engine:
    """espeak-ng, loaded for one sentence (:func:`synthesise`)."""

    def __init__(self) -> None:
        self.lib = ctypes.CDLL(espeakng_loader.get_library_path())
        self.lib.espeak_Initialize.restype = ctypes.c_int
        rate = self.lib.espeak_Initialize(SYNCHRONOUS, 0,
                                          espeakng_loader.get_data_path().encode(), 0)
        if rate <= 0:
            raise VoiceError("espeak-ng did not start")
        self.rate = int(rate)
        self.chunks: list[np.ndarray] = []
        self._callback = _CALLBACK(self._collect)   # kept: the library holds a pointer to it
        self.lib.espeak_SetSynthCallback(self._callback)

    def _collect(self, samples: Any, count: int, _events: int) -> int:
        if count > 0:
            self.chunks.append(np.ctypeslib.as_array(samples, shape=(count,)).copy())
        return 0

    def say(self, text: str, voice: Voice) -> np.ndarray:
        if self.lib.espeak_SetVoiceByName(voice.espeak_name.encode()) != 0:
            raise VoiceError(f"espeak-ng has no voice {voice.espeak_name!r}")
        self.lib.espeak_SetParameter(RATE, voice.speed, 0)
        self.lib.espeak_SetParameter(PITCH, voice.pitch, 0)
        data = text.encode()
        self.lib.espeak_ng_SetRandSeed(ctypes.c_long(SEED))
        if self.lib.espeak_Synth(data, len(data) + 1, 0, POSITION_CHARACTER, 0, CHARS_UTF8,
                                 None, None) != 0:
            raise VoiceError(f"espeak-ng could not say {text[:60]!r}")
        self.lib.espeak_Synchronize()
        return (np.concatenate(self.chunks) if self.chunks
                else np.zeros(0, dtype=np.int16)).astype(np.int16)

    def close(self) -> None:
        """Stop espeak-ng and unload the library, so that the next load starts afresh."""
        self.lib.espeak_Terminate()
        _ctypes.dlclose(self.lib._handle)


_LOCK = threading.Lock()   # one sentence at a time: the library's state is global


def synthesise(text: str, voice: Voice) -> tuple[np.ndarray, int]:
    """``text`` said in ``voice``: 16-bit mono samples and their rate (Hz). The samples
    depend on ``text`` and ``voice`` alone, not on what was said before in the process."""
    with _LOCK:
        e = _Engine()
        try:
            return e.say(text, voice), e.rate
        finally:
            e.close()


def check_voice(voice: Voice) -> None:
    """Raise :class:`VoiceError` when espeak-ng lacks ``voice``."""
    synthesise("", voice)


def wav_bytes(samples: np.ndarray, rate: int) -> bytes:
    """A 16-bit WAV file of ``samples``: mono, or one channel per row of ``(M, n)``."""
    channels = np.atleast_2d(samples)
    buffer = io.BytesIO()
    with wave.open(buffer, "wb") as w:
        w.setnchannels(len(channels))
        w.setsampwidth(2)
        w.setframerate(rate)
        w.writeframes(channels.T.astype(np.int16).tobytes())
    return buffer.getvalue()
