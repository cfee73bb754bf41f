"""Sound to utterances for ``companion chat --listen``: where the sound comes from (the
computer's default microphone through sounddevice and PortAudio, or a WAV file read in
blocks as if it were one) and the loop that passes it through the voice-activity detector
(dialogue/speech/vad.py), giving each utterance as soon as it has ended."""

from __future__ import annotations

import contextlib
import queue
from collections.abc import Callable, Iterable, Iterator
from pathlib import Path
from typing import Any

import numpy as np

from core.errors import UserError
from dialogue.speech.vad import SpeechStart, Utterance, UtteranceDetector
from dialogue.speech.wav import read_wav
from robot.audio import RATE, resampled

BLOCK_MS = 30           # each block the microphone gives (and a WAV file is read in)
POLL_S = 0.2            # how often the wait for the microphone's next block looks up


class MicrophoneError(UserError):
    """No audio input device, or PortAudio cannot open it."""


def block_samples(block_ms: int = BLOCK_MS) -> int:
    """Samples in a block of ``block_ms`` at 16 kHz."""
    return RATE * block_ms // 1000


def wav_blocks(path: Path, block_ms: int = BLOCK_MS) -> Iterator[np.ndarray]:
    """The first channel of the WAV file at ``path``, at 16 kHz, in int16 blocks of
    ``block_ms``, as a microphone would give them (the last one may be shorter)."""
    samples, rate = read_wav(path)
    if rate != RATE:
        samples = np.clip(np.round(resampled(samples, rate)), -32768, 32767).astype(np.int16)
    step = block_samples(block_ms)
    for i in range(0, len(samples), step):
        yield samples[i:i + step]


def _portaudio() -> Any:
    """The sounddevice module (PortAudio loaded), or a :class:`MicrophoneError`."""
    try:
        import sounddevice
    except OSError as exc:   # sounddevice raises OSError when libportaudio is missing
        raise MicrophoneError(f"cannot load PortAudio ({exc}); make setup installs Debian's "
                              "libportaudio2") from None
    return sounddevice


@contextlib.contextmanager
def microphone(block_ms: int = BLOCK_MS, device: int | str | None = None
               ) -> Iterator[Iterator[np.ndarray]]:
    """The default audio input (or ``device``), mono 16 kHz int16, as an endless iterator of
    blocks of ``block_ms``, while the block is open. A callback queues every block, so none
    is lost while the caller is busy decoding the last utterance. A
    :class:`MicrophoneError` when there is no input device or PortAudio cannot open it."""
    blocks: queue.Queue[np.ndarray] = queue.Queue()

    def _queue(data: np.ndarray, frames: int, time: Any, status: Any) -> None:
        blocks.put(data[:, 0].copy())

    stream = _open_input(block_ms, device, _queue)
    try:
        yield _drain(blocks)
    finally:
        stream.stop()
        stream.close()


def _open_input(block_ms: int, device: int | str | None,
                callback: Callable[[np.ndarray, int, Any, Any], None]) -> Any:
    """A started sounddevice InputStream (mono 16 kHz int16) that hands each block to
    ``callback``, or a :class:`MicrophoneError` saying why there is none."""
    sd = _portaudio()
    stream = None
    try:
        stream = sd.InputStream(samplerate=RATE, channels=1, dtype="int16", device=device,
                                blocksize=block_samples(block_ms), callback=callback)
        stream.start()
    except (sd.PortAudioError, ValueError) as exc:
        if stream is not None:
            stream.close()
        raise MicrophoneError(f"no audio input to listen to ({exc}): connect a microphone, "
                              "or transcribe a recording with --audio FILE.wav") from None
    return stream


def _drain(blocks: queue.Queue[np.ndarray]) -> Iterator[np.ndarray]:
    """The queued blocks, waiting for each (in short waits, so Ctrl-C is seen)."""
    while True:
        with contextlib.suppress(queue.Empty):
            yield blocks.get(timeout=POLL_S)


def utterances(blocks: Iterable[np.ndarray], detector: UtteranceDetector | None = None,
               on_start: Callable[[SpeechStart], None] | None = None) -> Iterator[Utterance]:
    """Each utterance in ``blocks`` (16 kHz int16), given as soon as the detector has heard
    its end, before the next block is read; at the end of the blocks, the one in progress.
    ``on_start`` hears of each utterance's start."""
    detector = detector or UtteranceDetector()
    for block in blocks:
        yield from _events(detector.feed(block), on_start)
    yield from _events(detector.finish(), on_start)


def _events(events: list[SpeechStart | Utterance],
            on_start: Callable[[SpeechStart], None] | None) -> Iterator[Utterance]:
    for event in events:
        if isinstance(event, Utterance):
            yield event
        elif on_start is not None:
            on_start(event)
