"""Keeping the household's voices and taking out the rest, before the recogniser hears it.

A TV in the room plays a presenter's voice about as loud, at the robot, as a person a few
metres away: one microphone channel cannot tell the two apart by level, and pocketsphinx
transcribes both. What does tell them apart is whose voice it is. A robot that lives with
the same people can learn their voices (the acoustic model is adapted to them for the same
reason), and a small recurrent network does so here: from the log spectrum of what the
microphones recorded it estimates, for every time-frequency cell, how much of it is a
household voice (a ratio mask; Huang et al., 2014, "Deep learning for monaural speech
separation", train such masks for known speakers). The recording is resynthesised with the
mask applied, and the recogniser decodes that instead. ``dialogue/speech/training/enhancer``
trains the network on the project's own lines mixed with other voices and noise; the TV's
programme of the household runs and of ``companion eval asr`` is never among them.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import torch
from torch import nn

from core.checkpoint import fp32_state, read_weights
from core.torch_threads import torch_threads
from dialogue.speech.config import SpeechModelError

N_FFT = 512             # 32 ms frames at 16 kHz: 257 frequency bins
HOP = 256               # 16 ms between frames
BINS = N_FFT // 2 + 1


def spectrum(samples: torch.Tensor) -> torch.Tensor:
    """The short-time Fourier transform (``(..., BINS, frames)``, complex) of 16 kHz
    ``samples`` (``(..., n)``)."""
    return torch.stft(samples, N_FFT, HOP, window=torch.hann_window(N_FFT),
                      return_complex=True)


def log_power(spec: torch.Tensor) -> torch.Tensor:
    """The network's input: log power of each cell, frames first (``(..., frames, BINS)``)."""
    return torch.log(spec.abs().square() + 1.0).transpose(-1, -2)


class MaskNet(nn.Module):
    """Log spectrum frames in, a mask in [0, 1] per frame and bin out: a projection, a
    bidirectional GRU over the whole sound (it is decoded after it ends), a projection."""

    def __init__(self, hidden: int, layers: int) -> None:
        super().__init__()
        self.register_buffer("scale", torch.ones(2, BINS))   # the features' mean and std
        self.inp = nn.Linear(BINS, 2 * hidden)
        self.rnn = nn.GRU(2 * hidden, hidden, num_layers=layers, batch_first=True,
                          bidirectional=True)
        self.out = nn.Linear(2 * hidden, BINS)

    def forward(self, features: torch.Tensor) -> torch.Tensor:
        """Masks (``(batch, frames, BINS)``) for log-power ``features`` of the same shape."""
        x = (features - self.scale[0]) / self.scale[1].clamp_min(1e-3)
        x, _ = self.rnn(torch.relu(self.inp(x)))
        return torch.sigmoid(self.out(x))


class VoiceEnhancer:
    """The trained :class:`MaskNet` applied to whole sounds (``enhance``), its mask raised
    to ``power`` first: above 1, a cell the net is unsure of is taken down further."""

    def __init__(self, path: Path, power: float = 1.0) -> None:
        state = read_weights(path, SpeechModelError, "companion train asr --only enhancer "
                                                     "makes it")
        self.power = power
        hp = state["hyperparameters"]
        self.net = MaskNet(int(hp["hidden"]), int(hp["layers"]))
        self.net.load_state_dict(fp32_state(state["state_dict"]))
        self.net.eval()
        self.floor = float(hp["mask_floor"])

    @torch.no_grad()
    def enhance(self, samples: np.ndarray, power: float | None = None) -> np.ndarray:
        """``samples`` (16 kHz floats) with what is not a household voice taken out, the
        mask raised to ``power`` (default: the enhancer's own)."""
        x = torch.as_tensor(np.asarray(samples, dtype=np.float32))
        if len(x) < N_FFT:
            return np.asarray(samples, dtype=np.float64)
        with torch_threads(1):   # one thread beside the simulation, as the other models
            spec = spectrum(x)
            mask = self.net(log_power(spec)[None])[0].T.pow(self.power if power is None else power)
            mask = mask.clamp_min(self.floor)
            y = torch.istft(spec * mask, N_FFT, HOP, window=torch.hann_window(N_FFT),
                            length=len(x))
        return y.double().numpy()

