"""The robot's speech recogniser: pocketsphinx on 16 kHz audio from its microphones.

The acoustic model is the en-US one inside the pocketsphinx wheel, adapted by this project
to the household's voices and rooms; the language model is the household one this project
estimates from its own lines (both made by dialogue/speech/training/, in
``assets/models/speech/``), with the wheel's pronunciation dictionary cut down to its
words. Each sound is decoded as one utterance with the cepstral mean taken over the whole
of it. A :class:`Transcript` carries the words, a confidence (the hypothesis's
posterior probability per word, a geometric mean, so that long and short lines compare) and
the speech's loudness over the noise, estimated from the signal alone. A sound whose speech
is too faint (a voice from another room, or lost in the TV) gives no words.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from dialogue.speech.beamformer import Steering, front_end, voice_direction
from dialogue.speech.config import SpeechConfig, SpeechModelError, load_speech_config
from robot.audio import RATE, REFERENCE_DB, resampled

FRAME = 320              # samples (20 ms) per frame of the loudness estimate
QUIET, LOUD = 10, 90     # percentiles of frame power taken as noise and as speech
ACOUSTIC_FILES = ("mdef", "means", "variances", "transition_matrices", "sendump", "feat.params",
                  "noisedict")


def wheel_model_dir() -> Path:
    """The folder of pocketsphinx's own en-US model files inside its wheel: the acoustic
    model in ``en-us/`` and the pronunciation dictionary ``cmudict-en-us.dict``."""
    from pocketsphinx import get_model_path

    return Path(get_model_path()) / "en-us"


@dataclass(frozen=True)
class Transcript:
    """What the recogniser made of a sound: ``text`` (lower case, may be empty),
    ``confidence`` in [0, 1], ``snr_db``, the speech's loudness over the noise, and
    ``direction``, where the voice came from (rad in the head's frame, positive to the
    left) when the head's microphones were steered at it, else None."""

    text: str
    confidence: float
    snr_db: float
    direction: float | None = None

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
    """pocketsphinx with the household language model; ``transcribe`` one sound at a time.
    ``microphones``: the head's microphones' positions (``(M, 2)``, m in the head's frame),
    for finding where a voice came from in their recordings; None: not looked for."""

    def __init__(self, cfg: SpeechConfig | None = None,
                 microphones: Sequence[Sequence[float]] | None = None) -> None:
        from pocketsphinx import Config, Decoder

        self.cfg = cfg or load_speech_config()
        self.microphones = None if microphones is None else np.asarray(microphones, float)
        m = self.cfg.model
        lm, words = m.path(m.language_model), m.path(m.dictionary)
        hmm = (wheel_model_dir() / "en-us" if m.acoustic_model is None
               else m.path(m.acoustic_model))
        for path in (lm, words, *(hmm / name for name in ACOUSTIC_FILES)):
            if not path.is_file():
                raise SpeechModelError(f"{path}: no such model file (companion train asr "
                                       "makes it)")
        # batch CMN: each sound normalised by its own cepstral mean (and the features
        # started afresh for each, in transcribe), so that a transcript does not depend on
        # the sounds heard before it
        self.decoder = Decoder(Config(hmm=str(hmm), lm=str(lm), dict=str(words),
                                      lw=m.language_weight, cmn="batch", loglevel="FATAL"))
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
        heard_snr = loudness(channels[0])[1]
        x, steer = self._front(channels)
        direction = (None if steer is None or self.microphones is None
                     else voice_direction(steer, self.microphones))
        if self.enhancer is not None:
            x = self.enhancer.enhance(x, self.mask_power(x))
        level, snr = loudness(x)
        if snr < self.cfg.min_snr_db or level < self.cfg.min_level_db:
            return Transcript("", 0.0, heard_snr, direction)
        pcm = np.clip(np.round(x), -32768, 32767).astype(np.int16).tobytes()
        d = self.decoder
        # the feature extraction's noise removal keeps a running estimate of the noise from
        # one sound to the next: started afresh, each sound is heard as on its own
        d.reinit_feat()
        d.start_utt()
        d.process_raw(pcm, full_utt=True)
        d.end_utt()
        hyp = d.hyp()
        text = hyp.hypstr.strip() if hyp is not None else ""
        n = len(text.split())
        confidence = float(hyp.prob) ** (1.0 / n) if n else 0.0
        return Transcript(text, min(max(confidence, 0.0), 1.0), heard_snr, direction)

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

    def understood(self, transcript: Transcript) -> bool:
        """Whether ``transcript`` is sure enough to act on (else: ask again)."""
        return transcript.words > 0 and transcript.confidence >= self.cfg.min_confidence
