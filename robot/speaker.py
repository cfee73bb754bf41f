"""What the robot says: logged as events, timed like speech, and with audio on, spoken into
WAV files in its own voice (robot/voices/: Piper or espeak-ng, in process)."""

from __future__ import annotations

import logging
from pathlib import Path

import numpy as np

from core.checkpoint import atomic_write_bytes
from core.events import EventLog
from robot.voices import Voice, VoiceError, check_voice, synthesise, wav_bytes

WORDS_PER_SECOND = 2.5  # a calm speaking rate
log = logging.getLogger(__name__)


def speech_seconds(text: str) -> float:
    """How long saying ``text`` takes (at least one second)."""
    return max(1.0, len(text.split()) / WORDS_PER_SECOND)


def write_wav(path: Path, samples: np.ndarray, rate: int) -> None:
    """Write ``samples`` to ``path`` as a WAV file, whole or not at all."""
    atomic_write_bytes(path, wav_bytes(samples, rate))


class Speaker:
    """Says sentences: each one becomes a ``say`` event with its duration.

    With ``audio_dir`` every sentence is also spoken in ``voice`` into
    ``audio_dir/NNNN.wav`` (NNNN counts the sentences from 0001) and the file name is added
    to its event as ``audio``. A sentence the voice cannot say is logged without audio.
    """

    def __init__(self, events: EventLog, audio_dir: str | Path | None = None,
                 voice: Voice | None = None) -> None:
        self.events = events
        self.said = 0
        self.voice = voice or Voice()
        self.folder = Path(audio_dir) if audio_dir is not None else None
        if self.folder is not None:
            check_voice(self.voice)
            self.folder.mkdir(parents=True, exist_ok=True)

    def say(self, text: str, **fields: object) -> float:
        """Log the sentence (spoken to WAV when audio is on) and return how long it takes
        to say (seconds)."""
        self.said += 1
        duration = speech_seconds(text)
        if self.folder is not None:
            name = f"{self.said:04d}.wav"
            try:
                write_wav(self.folder / name, *synthesise(text, self.voice))
                fields["audio"] = name
            except VoiceError as exc:
                log.warning("%s", exc)
        self.events.emit("say", text=text, duration=duration, **fields)
        return duration
