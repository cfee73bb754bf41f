"""What the robot says: logged as events, timed like speech, optionally rendered to WAV."""

from __future__ import annotations

import logging
import shutil
import subprocess
from pathlib import Path

from app.core.events import EventLog

WORDS_PER_SECOND = 2.5  # a calm speaking rate
ESPEAK = "espeak-ng"
log = logging.getLogger(__name__)


def speech_seconds(text: str) -> float:
    """How long saying ``text`` takes (at least one second)."""
    return max(1.0, len(text.split()) / WORDS_PER_SECOND)


class Speaker:
    """Says sentences: each one becomes a ``say`` event with its duration.

    With ``audio_dir`` and the ``espeak-ng`` binary on the PATH, every sentence is also
    rendered to ``audio_dir/NNNN.wav`` (NNNN counts the sentences from 0001) and the file
    name is added to its event as ``audio``. Without espeak-ng the sentences are only
    logged.
    """

    def __init__(self, events: EventLog, audio_dir: str | Path | None = None) -> None:
        self.events = events
        self.said = 0
        self._audio: tuple[str, Path] | None = None   # (espeak-ng binary, folder) when on
        if audio_dir is not None:
            espeak = shutil.which(ESPEAK)
            if espeak is None:
                log.warning("%s is not installed (`make tts`): speech is only logged", ESPEAK)
            else:
                self._audio = (espeak, Path(audio_dir))
                self._audio[1].mkdir(parents=True, exist_ok=True)

    def say(self, text: str, **fields: object) -> float:
        """Log the sentence (rendering it to WAV when enabled) and return how long it takes
        to say (seconds)."""
        self.said += 1
        duration = speech_seconds(text)
        if self._audio is not None:
            audio = self._render(text, *self._audio)
            if audio is not None:
                fields["audio"] = audio
        self.events.emit("say", text=text, duration=duration, **fields)
        return duration

    def _render(self, text: str, espeak: str, folder: Path) -> str | None:
        """Write the sentence to the next numbered WAV file; its name, or None on failure."""
        name = f"{self.said:04d}.wav"
        wpm = str(round(WORDS_PER_SECOND * 60))
        cmd = [espeak, "-s", wpm, "-w", str(folder / name), "--", text]
        try:
            subprocess.run(cmd, check=True, capture_output=True, timeout=30)
        except (OSError, subprocess.SubprocessError) as exc:
            log.warning("%s could not render %r: %s", ESPEAK, text, exc)
            return None
        return name
