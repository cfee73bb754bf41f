"""Taking the room's late reverberation out of the head's four microphones before the beam.

At 3 m from a talker in a furnished living room most of what reaches the robot is the
voice's own reverberation, and the TV across the room is heard almost only through the
room's; a beam, which can only favour a direction, gains little against either. Weighted
prediction error (WPE; Nakatani et al., 2010, "Speech dereverberation based on
variance-normalized delayed linear prediction"; Yoshioka and Nakatani, 2012, for several
microphones) predicts each microphone's late reverberation, at every frequency, from the
recording's own frames some time back (``taps`` frames, leaving out the ``delay`` most
recent so that the direct sound and early reflections stay) and subtracts it, the
prediction weighted by the inverse of the voice's power as it is re-estimated each round
(``iterations``). nara_wpe's implementation does the work, one frequency at a time
(``wpe_v8``: its batched form's output up to rounding, in a third of the time, and without
the 400 MB the batched form holds for ten seconds of four microphones); this module only
takes the recording to its short-time spectra and back.
"""

from __future__ import annotations

import numpy as np
from nara_wpe.utils import istft, stft
from nara_wpe.wpe import wpe_v8

from dialogue.speech.config import DereverberationConfig

FRAME, SHIFT = 512, 128   # samples: 32 ms frames every 8 ms at 16 kHz


def dereverberate(channels: np.ndarray, cfg: DereverberationConfig) -> np.ndarray:
    """``channels`` (``(M, n)`` at 16 kHz) with their late reverberation predicted and taken
    out, the same shape."""
    x = np.asarray(channels, dtype=np.float64)
    spec = stft(x, size=FRAME, shift=SHIFT)                      # (M, frames, bins)
    clean = wpe_v8(np.ascontiguousarray(spec.transpose(2, 0, 1)), taps=cfg.taps, delay=cfg.delay,
                   iterations=cfg.iterations, statistics_mode="full")
    out = istft(clean.transpose(1, 2, 0), size=FRAME, shift=SHIFT)[:, :x.shape[1]]
    return np.pad(out, ((0, 0), (0, x.shape[1] - out.shape[1])))
