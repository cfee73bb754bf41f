"""espeak-ng in this process: the library and its voice data from the ``espeakng-loader``
wheel, called through ctypes in its synchronous mode, each sentence coming back through a
callback as 16-bit samples (22,050 Hz).

espeak-ng keeps one global state per process, and some of it runs on from one sentence to
the next where its API cannot reset it (the same line said twice in a row came out
different), so the library is loaded, started and unloaded again for each sentence (about a
millisecond): a line sounds the same whatever the process said before it.
"""

from __future__ import annotations

import _ctypes
import ctypes
import threading
from typing import TYPE_CHECKING, Any

import espeakng_loader
import numpy as np

from robot.voices.errors import VoiceError

if TYPE_CHECKING:
    from robot.voices import Voice

SYNCHRONOUS = 2          # espeak_AUDIO_OUTPUT: samples handed to the callback as they come
POSITION_CHARACTER = 1   # espeak_POSITION_TYPE
CHARS_UTF8 = 1           # espeak_Synth flags
RATE, PITCH = 1, 3       # espeak_PARAMETER
SEED = 1                 # of espeak-ng's noise (breathy voices), set before each line
_CALLBACK = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.POINTER(ctypes.c_short), ctypes.c_int,
                             ctypes.c_void_p)
_LOCK = threading.Lock()   # one sentence at a time: the library's state is global


class _Engine:
    """espeak-ng, loaded for one sentence (:func:`say`)."""

    def __init__(self) -> None:
        self.lib = ctypes.CDLL(espeakng_loader.get_library_path())
        self.lib.espeak_Initialize.restype = ctypes.c_int
        rate = self.lib.espeak_Initialize(SYNCHRONOUS, 0,
                                          espeakng_loader.get_data_path().encode(), 0)
        if rate <= 0:
            raise VoiceError("espeak-ng did not start")
        self.rate = int(rate)
        self.chunks: list[np.ndarray] = []
        self._callback = _CALLBACK(self._collect)   # kept: the library holds a pointer to it
        self.lib.espeak_SetSynthCallback(self._callback)

    def _collect(self, samples: Any, count: int, _events: int) -> int:
        if count > 0:
            self.chunks.append(np.ctypeslib.as_array(samples, shape=(count,)).copy())
        return 0

    def say(self, text: str, voice: Voice) -> np.ndarray:
        """``text`` in ``voice``, as 16-bit samples at :attr:`rate`."""
        if self.lib.espeak_SetVoiceByName(voice.espeak_name.encode()) != 0:
            raise VoiceError(f"espeak-ng has no voice {voice.espeak_name!r}")
        self.lib.espeak_SetParameter(RATE, voice.speed, 0)
        self.lib.espeak_SetParameter(PITCH, voice.pitch, 0)
        data = text.encode()
        self.lib.espeak_ng_SetRandSeed(ctypes.c_long(SEED))
        if self.lib.espeak_Synth(data, len(data) + 1, 0, POSITION_CHARACTER, 0, CHARS_UTF8,
                                 None, None) != 0:
            raise VoiceError(f"espeak-ng could not say {text[:60]!r}")
        self.lib.espeak_Synchronize()
        return (np.concatenate(self.chunks) if self.chunks
                else np.zeros(0, dtype=np.int16)).astype(np.int16)

    def close(self) -> None:
        """Stop espeak-ng and unload the library, so that the next load starts afresh."""
        self.lib.espeak_Terminate()
        _ctypes.dlclose(self.lib._handle)


def say(text: str, voice: Voice) -> tuple[np.ndarray, int]:
    """``text`` said in the espeak-ng ``voice``: 16-bit mono samples and their rate (Hz)."""
    with _LOCK:
        e = _Engine()
        try:
            return e.say(text, voice), e.rate
        finally:
            e.close()
