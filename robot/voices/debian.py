"""Two synthesizers from Debian packages, run as programs: CMU Flite (``flite``, its voices
built in: ``kal``, ``kal16``, ``awb``, ``rms``, ``slt``) and Festival (``text2wave`` with a
voice package: ``kal_diphone`` from festvox-kallpc16k, ``cmu_us_slt_arctic_hts`` from
festvox-us-slt-hts). `make setup` installs them. Both are deterministic.

No model of the project is trained or tuned on these voices: they are the held-out
families of ``companion eval asr --voices held-out`` (docs/speech.md).
"""

from __future__ import annotations

import io
import shutil
import subprocess
import tempfile
import wave
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from robot.voices.errors import VoiceError

if TYPE_CHECKING:
    from robot.voices import Voice

OWN_PACE_WPM = 150        # a Voice's speed at which the synthesizer keeps its own pace
FLITE_VOICES = ("kal", "kal16", "awb", "rms", "slt")
FESTIVAL_VOICES = ("kal_diphone", "cmu_us_slt_arctic_hts")


def _program(name: str, package: str) -> str:
    path = shutil.which(name)
    if path is None:
        raise VoiceError(f"{name} is not installed (Debian's {package}; make setup installs "
                         "it)")
    return path


def _samples(wav: bytes) -> tuple[np.ndarray, int]:
    with wave.open(io.BytesIO(wav)) as w:
        if w.getsampwidth() != 2:
            raise VoiceError("the synthesizer wrote samples other than 16-bit")
        samples = np.frombuffer(w.readframes(w.getnframes()), dtype="<i2")
        return samples[::w.getnchannels()].astype(np.int16), w.getframerate()


def _run(command: list[str], text: str, out: Path) -> bytes:
    done = subprocess.run(command, capture_output=True, timeout=60, check=False)
    if done.returncode != 0 or not out.is_file():
        raise VoiceError(f"{Path(command[0]).name} could not say {text[:60]!r}: "
                         f"{done.stderr.decode(errors='replace')[-200:]}")
    return out.read_bytes()


def say(text: str, voice: Voice) -> tuple[np.ndarray, int]:
    """``text`` said by the ``flite`` or ``festival`` ``voice``: 16-bit samples and their
    rate (Hz); an empty text gives no samples."""
    if not text.strip():
        return np.zeros(0, dtype=np.int16), 16000
    stretch = f"{OWN_PACE_WPM / voice.speed:.3f}"
    with tempfile.TemporaryDirectory() as folder:
        out, line = Path(folder) / "line.wav", Path(folder) / "line.txt"
        line.write_text(text, encoding="utf-8")
        if voice.engine == "flite":
            command = [_program("flite", "flite"), "-voice", voice.name, "-f", str(line),
                       "--setf", f"duration_stretch={stretch}", "-o", str(out)]
        else:
            command = [_program("text2wave", "festival"), str(line), "-o", str(out), "-eval",
                       f"(begin (voice_{voice.name}) "
                       f"(Parameter.set 'Duration_Stretch {stretch}))"]
        return _samples(_run(command, text, out))
