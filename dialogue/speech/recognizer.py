"""The robot's speech recogniser: one of two decoders (dialogue/speech/engines.py) on
16 kHz audio from its microphones, behind one interface.

The shipped decoder is faster-whisper with Whisper tiny.en from a wheel; pocketsphinx with
the household's adapted acoustic model and language model is the other (``model.engine``;
docs/speech.md compares them). Before either, the head's four
microphones may pass the household front end (dereverberation, the beam, the voice
enhancer; ``model``). A :class:`Transcript` carries
the words, a confidence (the decoder's, per word or per token, so that long and short lines
compare) and the speech's loudness over the noise, estimated from the signal alone. A sound
whose speech is too faint (a voice from another room, or lost in the TV) gives no words.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from dialogue.speech.beamformer import Steering, front_end, voice_direction
from dialogue.speech.config import SpeechConfig, load_speech_config
from dialogue.speech.engines import make_engine
from robot.audio import RATE, REFERENCE_DB, resampled

FRAME = 320              # samples (20 ms) per frame of the loudness estimate
QUIET, LOUD = 10, 90     # percentiles of frame power taken as noise and as speech
@dataclass(frozen=True)
class Transcript:
    """What the recogniser made of a sound: ``text`` (lower case, may be empty),
    ``confidence`` in [0, 1], ``snr_db``, the speech's loudness over the noise,
    ``direction``, where the voice came from (rad in the head's frame, positive to the
    left) when the head's microphones were steered at it, else None, and ``level_db``, the
    speech's level at the (first) microphone (dB SPL)."""

    text: str
    confidence: float
    snr_db: float
    direction: float | None = None
    level_db: float = -math.inf

    @property
    def words(self) -> int:
        """How many words were recognised."""
        return len(self.text.split())


def _frame_power(samples: np.ndarray) -> np.ndarray | None:
    """The mean power of each :data:`FRAME` of ``samples``; None for under two frames."""
    x = np.asarray(samples, dtype=np.float64)
    n = len(x) // FRAME
    return None if n < 2 else (x[:n * FRAME].reshape(n, FRAME) ** 2).mean(axis=1) + 1e-3


def _db_spl(power: float) -> float:
    return REFERENCE_DB + 10.0 * math.log10(power / 32768.0 ** 2)


def loudness(samples: np.ndarray) -> tuple[float, float]:
    """The speech's level (dB SPL at the calibrated microphones) and how far it stands
    above the noise (dB), from the loud and the quiet frames of a sound that holds both,
    as a voice-activity detector judges them."""
    power = _frame_power(samples)
    if power is None:
        return -math.inf, -math.inf
    noise, loud = np.percentile(power, [QUIET, LOUD])
    speech = max(loud - noise, 1e-6)
    return _db_spl(speech), 10.0 * math.log10(max(speech / noise, 1e-6))


def noise_floor(samples: np.ndarray) -> float:
    """The level (dB SPL) of a sound's quiet frames: the room's noise under the speech."""
    power = _frame_power(samples)
    return -math.inf if power is None else _db_spl(float(np.percentile(power, QUIET)))


class SpeechRecognizer:
    """The configured decoder (``model.engine``) behind the household front end;
    ``transcribe`` one sound at a time. ``microphones``: the head's microphones' positions
    (``(M, 2)``, m in the head's frame), for finding where a voice came from in their
    recordings; None: not looked for."""

    def __init__(self, cfg: SpeechConfig | None = None,
                 microphones: Sequence[Sequence[float]] | None = None) -> None:
        self.cfg = cfg or load_speech_config()
        self.microphones = None if microphones is None else np.asarray(microphones, float)
        m = self.cfg.model
        self.engine = make_engine(m)
        self.enhancer = None
        if m.enhancer is not None:
            from dialogue.speech.enhancer import VoiceEnhancer

            self.enhancer = VoiceEnhancer(m.path(m.enhancer), m.mask_power)

    def transcribe(self, samples: np.ndarray, rate: int = RATE) -> Transcript:
        """The words in ``samples`` (mono, or ``(M, n)`` from the head's microphones; any
        rate), their confidence, the sound's SNR as the first microphone recorded it (how
        well the robot hears from where it is) and, through the beam, where the voice came
        from. Whether it is speech at all is judged after the enhancer, when there is one, has
        taken out what is not a household voice."""
        channels = np.stack([resampled(c, rate) for c in np.atleast_2d(samples)])
        heard_level, heard_snr = loudness(channels[0])
        x, steer = self._front(channels)
        direction = (None if steer is None or self.microphones is None
                     else voice_direction(steer, self.microphones))
        if self.enhancer is not None and self.cfg.model.mask_output:
            x = self.enhancer.enhance(x, self.mask_power(x))
        level, snr = loudness(x)
        if snr < self.cfg.min_snr_db or level < self.cfg.min_level_db:
            return Transcript("", 0.0, heard_snr, direction, heard_level)
        text, confidence = self.engine.decode(x)
        return Transcript(text, min(max(confidence, 0.0), 1.0) if text else 0.0, heard_snr,
                          direction, heard_level)

    def _front(self, channels: np.ndarray) -> tuple[np.ndarray, Steering | None]:
        """The one channel decoded of ``channels`` (``(M, n)`` at 16 kHz; see
        :meth:`one_channel`) and the beam's steering, when there is a beam."""
        if len(channels) == 1:
            return channels[0], None
        m = self.cfg.model
        return front_end(channels, self.enhancer if m.beamformer else None,
                         m.beamformer_loading, m.dereverberation)

    def one_channel(self, channels: np.ndarray) -> np.ndarray:
        """What is decoded of the head's microphones (``(M, n)`` at 16 kHz): their late
        reverberation taken out (``model.dereverberation``), then the beamformer's output
        (``model.beamformer``), else the first microphone."""
        return self._front(channels)[0]

    def mask_power(self, samples: np.ndarray) -> float:
        """The power the enhancer's mask is raised to for ``samples`` (16 kHz): the
        enhancer's sharper one (``mask_power``) where the recording's noise floor says the
        room is loud (``loud_room_db``), the net's own mask (1) in a quiet one."""
        m = self.cfg.model
        sharp = m.mask_power if self.enhancer is None else self.enhancer.power
        loud = m.loud_room_db is None or noise_floor(samples) >= m.loud_room_db
        return sharp if loud else 1.0

    @property
    def min_confidence(self) -> float:
        """The confidence a transcript needs to be acted on: the decoder's own threshold."""
        return self.cfg.acting_confidence

    def understood(self, transcript: Transcript) -> bool:
        """Whether ``transcript`` is sure enough to act on (else: ask again)."""
        return transcript.words > 0 and transcript.confidence >= self.min_confidence
