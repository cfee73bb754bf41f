"""Steering the head's four microphones at the voice: a minimum-variance distortionless
response (MVDR) beamformer whose statistics come from the voice enhancer's mask.

For every frequency, the enhancer's network says which cells of each microphone's recording
hold a household voice (its mask; the median over the microphones). The cells weighted by
the mask give the voice's spatial covariance, the rest the background's: the mask-based
statistics of Heymann, Drude and Haeb-Umbach (2016, "Neural network based spectral mask
estimation for acoustic beamforming"). Where the voice comes from, as the microphones
see it, is the principal generalised eigenvector of the two (the voice's covariance
whitened by the background's and coloured back; Markovich, Gannot and Cohen, 2009,
"Multichannel eigenspace beamforming in a reverberant noisy environment"), scaled to the
first microphone: no positions and no direction are needed. The MVDR filter (Capon, 1969)
then passes what comes from there as the first microphone hears it and lets through as
little of the rest as it can: the TV's direct sound, and much of the room's reverberation,
the voice's own included. The recogniser takes the beam's single channel through the
enhancer, as it takes one microphone's.
"""

from __future__ import annotations

import numpy as np
import torch

from app.core.torch_threads import torch_threads
from dialogue.speech.enhancer import HOP, N_FFT, VoiceEnhancer, log_power, spectrum


def _covariance(weight: torch.Tensor, spec: torch.Tensor) -> torch.Tensor:
    """The weighted spatial covariance (``(bins, M, M)``) of ``spec`` (``(M, bins, frames)``)
    with ``weight`` (``(bins, frames)``) over the frames."""
    total = weight.sum(dim=1).clamp_min(1e-6)[:, None, None]
    return torch.einsum("ft,mft,nft->fmn", weight.to(spec.dtype), spec, spec.conj()) / total


@torch.no_grad()
def mvdr_weights(channels: np.ndarray, enhancer: VoiceEnhancer, loading: float
                 ) -> torch.Tensor:
    """The beam's weights (``(bins, M)``, complex) for ``channels`` (``(M, n)`` at 16 kHz,
    at least one frame): the MVDR filter, the first microphone the reference, at whatever
    the enhancer's mask takes for the voice; the background's covariance loaded with
    ``loading`` times its mean power on the diagonal (so that a frequency the mask left
    nearly empty is not inverted wildly)."""
    x = torch.as_tensor(np.asarray(channels, dtype=np.float32))
    with torch_threads(1):
        spec = spectrum(x)                                          # (M, bins, frames)
        mask = enhancer.net(log_power(spec)).median(dim=0).values.T.double()
        spec = spec.to(torch.complex128)
        voice, noise = _covariance(mask, spec), _covariance(1.0 - mask, spec)
        power = torch.diagonal(noise, dim1=1, dim2=2).real.mean(dim=1)
        noise = noise + loading * power[:, None, None] * torch.eye(len(x), dtype=spec.dtype)
        # the voice's direction: the principal generalised eigenvector of the two
        # covariances (the voice's covariance whitened by the background's), coloured back
        chol = torch.linalg.cholesky(noise)
        whitened = torch.linalg.solve_triangular(chol, voice, upper=False)
        whitened = torch.linalg.solve_triangular(chol, whitened.mH, upper=False).mH
        steer = chol @ torch.linalg.eigh(whitened)[1][:, :, -1:]       # (bins, M, 1)
        steer = steer / steer[:, :1]                                      # the first microphone's
        towards = torch.linalg.solve(noise, steer)
        return (towards / (steer.mH @ towards))[:, :, 0]


def apply_weights(weights: torch.Tensor, channels: np.ndarray) -> np.ndarray:
    """``channels`` (``(M, n)``) through the beam of ``weights``: one channel of n samples."""
    x = torch.as_tensor(np.asarray(channels, dtype=np.float32))
    beam = torch.einsum("fm,mft->ft", weights.conj(), spectrum(x).to(torch.complex128))
    window = torch.hann_window(N_FFT, dtype=torch.float64)
    return torch.istft(beam, N_FFT, HOP, window=window, length=x.shape[1]).numpy()


def beamform(channels: np.ndarray, enhancer: VoiceEnhancer, loading: float) -> np.ndarray:
    """One channel (16 kHz floats) from ``channels`` (``(M, n)``): the MVDR beam of
    :func:`mvdr_weights` (the first microphone as it is when under one frame long)."""
    if np.shape(channels)[1] < N_FFT:
        return np.asarray(channels[0], dtype=np.float64)
    return apply_weights(mvdr_weights(channels, enhancer, loading), channels)
