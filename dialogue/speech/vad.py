"""Where an utterance starts and ends in a stream of sound: Silero VAD, streamed.

Silero VAD v6 (MIT), the ONNX model that ships inside the faster-whisper wheel
(``faster_whisper/assets/silero_vad_v6.onnx``; nothing is downloaded), gives each window of
:data:`WINDOW` samples (32 ms at 16 kHz) a probability of speech. It is opened once, on first
use, with onnxruntime on one thread, and run window by window with its recurrent state and
the last :data:`CONTEXT` samples carried from one call to the next, so that a stream fed in
blocks of any length gives the same probabilities as the whole sound at once.

:class:`UtteranceDetector` turns them into utterances (settings ``vad:`` in
config/speech.yaml): speech starts at a window at or over ``threshold``, ends after
``min_silence_ms`` below ``threshold - 0.15`` (Silero's end threshold), and is kept only when
it lasted ``min_speech_ms``; ``pre_roll_ms`` of sound is kept before its start (and as much
after its end), so that the first word is not cut. The live microphone of ``companion chat
--listen`` feeds it (dialogue/speech/listen.py), and so does each recording of a household
run (behaviours/voice_streams.py), whose speech starts stop the robot's replies.
:func:`speech_present` says whether a short sound holds speech.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from dialogue.speech.config import SpeechModelError, VadConfig, load_speech_config
from robot.audio import RATE

if TYPE_CHECKING:
    import onnxruntime

WINDOW = 512            # samples the model judges at a time (32 ms at 16 kHz)
CONTEXT = 64            # samples of the window before that the model sees with each window
END_MARGIN = 0.15       # in speech, a window is silence below threshold minus this (Silero's)
STATE_SHAPE = (1, 1, 128)
MODEL_FILE = "silero_vad_v6.onnx"


def model_path() -> Path:
    """Silero VAD v6 inside the installed faster-whisper wheel."""
    from faster_whisper.utils import get_assets_path

    return Path(get_assets_path()) / MODEL_FILE


@functools.cache
def _session() -> onnxruntime.InferenceSession:
    """The model, opened once, on one thread."""
    import onnxruntime

    path = model_path()
    if not path.is_file():
        raise SpeechModelError(f"{path}: Silero VAD is missing from the faster-whisper wheel "
                               "(make setup installs the pinned faster-whisper)")
    opts = onnxruntime.SessionOptions()
    opts.intra_op_num_threads = 1
    opts.inter_op_num_threads = 1
    opts.log_severity_level = 3
    return onnxruntime.InferenceSession(str(path), sess_options=opts,
                                        providers=["CPUExecutionProvider"])


class SileroStream:
    """Silero VAD over one stream: each call to :meth:`probabilities` continues where the
    last one stopped (its state, the last samples, a partial window held back)."""

    def __init__(self) -> None:
        self._h = np.zeros(STATE_SHAPE, np.float32)
        self._c = np.zeros(STATE_SHAPE, np.float32)
        self._context = np.zeros(CONTEXT, np.float32)
        self._pending = np.zeros(0, np.float32)

    def probabilities(self, block: np.ndarray) -> np.ndarray:
        """The speech probability of each window completed by ``block`` (16 kHz, int16
        scale), in order; samples short of a window wait for the next block."""
        x = np.concatenate([self._pending, np.asarray(block, np.float32) / 32768.0])
        n = len(x) // WINDOW
        self._pending = x[n * WINDOW:]
        if n == 0:
            return np.zeros(0, np.float32)
        joined = np.concatenate([self._context, x[:n * WINDOW]])
        rows = np.lib.stride_tricks.sliding_window_view(joined, CONTEXT + WINDOW)[::WINDOW]
        probs, self._h, self._c = _session().run(
            None, {"input": np.ascontiguousarray(rows), "h": self._h, "c": self._c})
        self._context = x[n * WINDOW - CONTEXT:n * WINDOW].copy()
        return np.asarray(probs, np.float32).reshape(-1)


def speech_probability(samples: np.ndarray) -> np.ndarray:
    """The speech probability of each whole :data:`WINDOW` of ``samples`` (16 kHz, int16
    scale), from a fresh model state."""
    return SileroStream().probabilities(samples)


def speech_present(samples: np.ndarray, cfg: VadConfig | None = None) -> bool:
    """Whether ``samples`` (16 kHz, int16 scale; say the last half second) hold speech: a
    run of windows at or over the threshold at least ``min_speech_ms`` long (at least one
    window)."""
    cfg = cfg or load_speech_config().vad
    loud = speech_probability(samples) >= cfg.threshold
    need = max(1, round(cfg.min_speech_ms * RATE / 1000 / WINDOW))
    run = longest = 0
    for is_speech in loud:
        run = run + 1 if is_speech else 0
        longest = max(longest, run)
    return longest >= need


@dataclass(frozen=True)
class SpeechStart:
    """Speech began at sample ``start`` of the stream (reported once it has lasted
    ``min_speech_ms``)."""

    start: int

    @property
    def start_s(self) -> float:
        """``start`` in seconds from the start of the stream."""
        return self.start / RATE


@dataclass(frozen=True)
class Utterance:
    """One utterance: its speech from sample ``start`` to ``end`` of the stream, decided at
    ``decided`` (the samples judged by then), and ``samples`` (int16), the speech with the
    pre-roll before it and as much after it as was fed."""

    start: int
    end: int
    decided: int
    samples: np.ndarray

    @property
    def start_s(self) -> float:
        """Where the speech began, in seconds from the start of the stream."""
        return self.start / RATE

    @property
    def end_s(self) -> float:
        """Where the speech ended, in seconds from the start of the stream."""
        return self.end / RATE


Event = SpeechStart | Utterance


class _Tape:
    """The stream's recent samples, from sample ``first`` on."""

    def __init__(self) -> None:
        self.first = 0
        self._chunks: list[np.ndarray] = []

    def append(self, block: np.ndarray) -> None:
        self._chunks.append(block)

    def drop_before(self, index: int) -> None:
        while self._chunks and self.first + len(self._chunks[0]) <= index:
            self.first += len(self._chunks.pop(0))

    def slice(self, begin: int, end: int) -> np.ndarray:
        whole = np.concatenate(self._chunks) if self._chunks else np.zeros(0, np.int16)
        return whole[max(begin - self.first, 0):max(end - self.first, 0)].copy()


class UtteranceDetector:
    """Feed it a stream of 16 kHz int16 blocks of any length; it says when an utterance
    starts (:class:`SpeechStart`) and when it has ended (:class:`Utterance`, with its
    samples), as soon as ``min_silence_ms`` of silence follows the speech."""

    def __init__(self, cfg: VadConfig | None = None) -> None:
        self.cfg = cfg or load_speech_config().vad
        self._model = SileroStream()
        self._tape = _Tape()
        self.fed = 0            # samples fed so far
        self.judged = 0         # samples the model has judged so far (whole windows)
        self._start: int | None = None
        self._silence_from: int | None = None
        self._announced = False
        ms = RATE / 1000
        self._pad = round(self.cfg.pre_roll_ms * ms)
        self._min_silence = round(self.cfg.min_silence_ms * ms)
        self._min_speech = round(self.cfg.min_speech_ms * ms)
        self._max = round(self.cfg.max_utterance_s * RATE)
        self._end_threshold = max(self.cfg.threshold - END_MARGIN, 0.01)

    @property
    def speaking(self) -> bool:
        """Whether an utterance has started (and lasted ``min_speech_ms``) and not ended."""
        return self._announced

    def feed(self, block: np.ndarray) -> list[Event]:
        """What ``block`` (1-D, 16 kHz, int16) completes: speech starts and utterances."""
        samples = np.asarray(block)
        if samples.ndim != 1:
            raise ValueError(f"one channel of samples, got the shape {samples.shape}")
        samples = samples.astype(np.int16, copy=True)
        self._tape.append(samples)
        self.fed += len(samples)
        events: list[Event] = []
        for p in self._model.probabilities(samples):
            events.extend(self._step(float(p)))
            self.judged += WINDOW
        self._tape.drop_before((self.judged if self._start is None else self._start) - self._pad)
        return events

    def finish(self) -> list[Event]:
        """The end of the stream: the utterance in progress, if any, ends here."""
        if self._start is None:
            return []
        end = self.judged if self._silence_from is None else self._silence_from
        return self._close(end, self.judged)

    def _step(self, p: float) -> list[Event]:
        """Judge the window that starts at ``self.judged``, of speech probability ``p``."""
        at, now = self.judged, self.judged + WINDOW
        if self._start is None:
            if p >= self.cfg.threshold:
                self._start, self._silence_from, self._announced = at, None, False
                return self._announce(now)
            return []
        if p >= self.cfg.threshold:
            self._silence_from = None
        elif p < self._end_threshold and self._silence_from is None:
            self._silence_from = at
        events = self._announce(now)
        if self._silence_from is not None and now - self._silence_from >= self._min_silence:
            events.extend(self._close(self._silence_from, now))
        elif now - self._start >= self._max:
            events.extend(self._close(now, now))
        return events

    def _announce(self, now: int) -> list[Event]:
        """A :class:`SpeechStart` once the speech so far has lasted ``min_speech_ms``."""
        assert self._start is not None
        speech_end = now if self._silence_from is None else self._silence_from
        if self._announced or speech_end - self._start < self._min_speech:
            return []
        self._announced = True
        return [SpeechStart(self._start)]

    def _close(self, end: int, now: int) -> list[Event]:
        """End the utterance in progress at ``end`` (``now`` judged): it, if it lasted."""
        assert self._start is not None
        start, announced = self._start, self._announced
        self._start, self._silence_from, self._announced = None, None, False
        if not announced:
            return []
        samples = self._tape.slice(start - self._pad, min(end + self._pad, now))
        return [Utterance(start, end, now, samples)]
