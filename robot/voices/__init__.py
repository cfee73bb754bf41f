"""Voices: the robot's and each person's, synthesised in this process.

A :class:`Voice` names its engine and, within it, a voice:

- ``espeak-ng`` (robot/voices/espeak.py; the library and its voices inside the
  ``espeakng-loader`` wheel): a language and accent such as ``en-us``, ``en`` or ``en-029``,
  an optional variant (``f1``-``f5`` female, ``m1``-``m7`` male, ``klatt``...), a pitch
  (0-99) and a speed (words a minute). Light, and robotic.
- ``piper`` (robot/voices/piper.py): a neural voice from a wheel (``joe``), at a speed and
  with a vocal-tract scale (``tract``), so that one recorded speaker gives people of other
  builds.
- ``flite`` and ``festival`` (robot/voices/debian.py): Debian's CMU Flite and Festival, at a
  speed; the voices no model of the project is tuned on.

:func:`synthesise` gives 16-bit samples that depend on the text and the voice alone, never
on what the process said before, so that runs, tests and training sounds do not depend on
their order.
"""

from __future__ import annotations

import io
import wave
from typing import Literal, Self

import numpy as np
from pydantic import Field, field_validator, model_validator

from core.config_files import StrictModel
from robot.voices import debian, espeak, piper
from robot.voices.errors import VoiceError

Engine = Literal["espeak-ng", "piper", "flite", "festival"]
__all__ = ["PEOPLE_VOICES", "Voice", "VoiceError", "check_voice", "synthesise", "wav_bytes"]
_NAMES = {"piper": tuple(piper.PIPER_VOICES), "flite": debian.FLITE_VOICES,
          "festival": debian.FESTIVAL_VOICES}


class Voice(StrictModel):
    """A voice of ``engine``: ``name`` (espeak-ng: language and accent; the others: the
    voice), ``variant`` and ``pitch`` (0-99; espeak-ng only), ``speed`` (words a minute)
    and ``tract`` (Piper only: the vocal tract shorter by this factor, pitch and formants
    as much higher)."""

    engine: Engine = "espeak-ng"
    name: str = Field(default="en-us", min_length=1, max_length=40)
    variant: str | None = Field(default=None, min_length=1, max_length=20)
    pitch: int = Field(default=50, ge=0, le=99)
    speed: int = Field(default=150, ge=80, le=450)
    tract: float = Field(default=1.0, ge=0.8, le=1.25)

    @field_validator("name", "variant")
    @classmethod
    def _plain(cls, value: str | None) -> str | None:
        if value is not None and not value.replace("-", "").replace("_", "").isalnum():
            raise ValueError("letters, digits, '-' and '_' only")
        return value

    @model_validator(mode="after")
    def _known(self) -> Self:
        if self.tract != 1.0 and self.engine != "piper":
            raise ValueError("tract is Piper's; espeak-ng's pitch and variant, Flite's and "
                             "Festival's voices set their own")
        if self.engine != "espeak-ng":
            if self.name not in _NAMES[self.engine]:
                raise ValueError(f"{self.engine} has no voice {self.name!r} (one of "
                                 f"{', '.join(_NAMES[self.engine])})")
            if self.variant is not None or self.pitch != 50:
                raise ValueError(f"variant and pitch are espeak-ng's; {self.engine} has "
                                 "neither")
        return self

    @property
    def label(self) -> str:
        """How reports name it: ``engine:name[+variant][*tract]``."""
        tract = "" if self.tract == 1.0 else f"*{self.tract:g}"
        return f"{self.engine}:{self.espeak_name}{tract}"

    @property
    def espeak_name(self) -> str:
        """The name espeak-ng selects it by: ``name`` or ``name+variant``."""
        return self.name if self.variant is None else f"{self.name}+{self.variant}"


# Voices people get when their scenario gives none, in the order they are listed: Piper's
# neural voice as three people of different build and pace, and three of espeak-ng's formant
# voices, so that each person of a household sounds like themselves and no evaluation hears
# one synthesizer only; all General American at an unhurried pace. Chosen on the household's
# spoken requests (docs/speech.md, Choosing the decoder): the recogniser hears Piper's voice
# best (WER 0.11-0.13 at 1 m for its two other builds), espeak-ng's f5, f2 and klatt4 next
# (its m1-m7 and its British, Scottish and Caribbean accents far worse). The held-out
# families (Flite, Festival) never chose one of them.
PEOPLE_VOICES = (
    Voice(engine="piper", name="joe", speed=140),
    Voice(name="en-us", variant="f5", pitch=70, speed=125),
    Voice(engine="piper", name="joe", speed=130, tract=1.18),
    Voice(engine="piper", name="joe", speed=125, tract=0.9),
    Voice(name="en-us", variant="f2", pitch=60, speed=135),
    Voice(name="en-us", variant="klatt4", pitch=52, speed=130),
)


def synthesise(text: str, voice: Voice) -> tuple[np.ndarray, int]:
    """``text`` said in ``voice``: 16-bit mono samples and their rate (Hz)."""
    if voice.engine == "espeak-ng":
        return espeak.say(text, voice)
    if voice.engine == "piper":
        return piper.say(text, voice)
    return debian.say(text, voice)


def check_voice(voice: Voice) -> None:
    """Raise :class:`VoiceError` when ``voice``'s engine lacks it or is not installed."""
    synthesise("" if voice.engine == "espeak-ng" else "yes", voice)


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
