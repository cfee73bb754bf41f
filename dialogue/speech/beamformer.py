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
enhancer, as it takes one microphone's. The same transfer functions, fitted by a plane wave
over the microphones' known positions, say where the voice came from
(:func:`voice_direction`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import torch

from core.torch_threads import torch_threads
from dialogue.speech.config import DereverberationConfig
from dialogue.speech.dereverberation import dereverberate
from dialogue.speech.enhancer import HOP, N_FFT, VoiceEnhancer, log_power, spectrum
from robot.audio import RATE, SPEED_OF_SOUND

# the bins a voice's direction is read from: all but the lowest, where microphones 7-10 cm
# apart hardly differ in phase, and the edge of the band (docs/speech.md, *Where a voice
# comes from*)
DIRECTION_BAND_HZ = (200.0, 7900.0)


def _covariance(weight: torch.Tensor, spec: torch.Tensor) -> torch.Tensor:
    """The weighted spatial covariance (``(bins, M, M)``) of ``spec`` (``(M, bins, frames)``)
    with ``weight`` (``(bins, frames)``) over the frames."""
    total = weight.sum(dim=1).clamp_min(1e-6)[:, None, None]
    return torch.einsum("ft,mft,nft->fmn", weight.to(spec.dtype), spec, spec.conj()) / total


@dataclass(frozen=True)
class Steering:
    """What the mask says of one recording of the head's microphones, per frequency bin:
    ``steer`` (``(bins, M)``), the voice's relative transfer function to each microphone
    (the first's is 1); ``weights`` (``(bins, M)``), the MVDR filter towards it."""

    steer: torch.Tensor
    weights: torch.Tensor


@torch.no_grad()
def steering(channels: np.ndarray, enhancer: VoiceEnhancer, loading: float) -> Steering:
    """The voice's :class:`Steering` in ``channels`` (``(M, n)`` at 16 kHz, at least one
    frame): the MVDR filter, the first microphone the reference, at whatever the enhancer's
    mask takes for the voice; the background's covariance loaded with ``loading`` times its
    mean power on the diagonal (so that a frequency the mask left nearly empty is not
    inverted wildly)."""
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
        weights = (towards / (steer.mH @ towards))[:, :, 0]
    return Steering(steer[:, :, 0], weights)


def voice_direction(steer: Steering, positions: np.ndarray) -> float:
    """Where the voice came from (rad in the head's frame: 0 straight ahead, positive to
    the left) for microphones at ``positions`` (``(M, 2)``, m in that frame): the azimuth,
    searched by whole degrees, whose plane wave best fits the voice's transfer functions over
    :data:`DIRECTION_BAND_HZ`, each bin counted alike (as GCC-PHAT weighs them: the loud low
    bins, where four microphones a few centimetres apart hardly differ in phase, do not
    outvote the rest). It works on the mask's estimate of the voice, not on the raw
    recording, so the TV does not pull it towards itself."""
    freqs = np.fft.rfftfreq(N_FFT, 1.0 / RATE)
    band = (freqs >= DIRECTION_BAND_HZ[0]) & (freqs <= DIRECTION_BAND_HZ[1])
    azimuths = np.radians(np.arange(-180.0, 180.0, 1.0))
    towards = np.stack([np.cos(azimuths), np.sin(azimuths)], axis=1)        # (A, 2)
    delays = -(towards @ np.asarray(positions, dtype=np.float64).T) / SPEED_OF_SOUND
    delays -= delays[:, :1]                                                 # behind the first
    plane = np.exp(-2j * np.pi * freqs[band, None, None] * delays[None])    # (F, A, M)
    h = steer.steer.numpy()[band]                                           # (F, M)
    h = h / np.linalg.norm(h, axis=1, keepdims=True).clip(1e-12)
    fit = (np.abs(np.einsum("fam,fm->fa", plane.conj(), h)) ** 2).sum(axis=0)   # (A,)
    return float(azimuths[int(np.argmax(fit))])


def apply_weights(weights: torch.Tensor, channels: np.ndarray) -> np.ndarray:
    """``channels`` (``(M, n)``) through the beam of ``weights``: one channel of n samples."""
    x = torch.as_tensor(np.asarray(channels, dtype=np.float32))
    beam = torch.einsum("fm,mft->ft", weights.conj(), spectrum(x).to(torch.complex128))
    window = torch.hann_window(N_FFT, dtype=torch.float64)
    return torch.istft(beam, N_FFT, HOP, window=window, length=x.shape[1]).numpy()


def front_end(channels: np.ndarray, enhancer: VoiceEnhancer | None, loading: float,
              dereverberation: DereverberationConfig | None = None
              ) -> tuple[np.ndarray, Steering | None]:
    """One channel (16 kHz floats) from ``channels`` (``(M, n)``) and the beam's
    :class:`Steering`: the late reverberation taken out first when ``dereverberation`` says
    how, then the MVDR beam that ``enhancer``'s mask steers; without an enhancer, or under
    one frame long, the first microphone as it is (and no steering)."""
    if dereverberation is not None:
        channels = dereverberate(channels, dereverberation)
    if enhancer is None or np.shape(channels)[1] < N_FFT:
        return np.asarray(channels[0], dtype=np.float64), None
    steer = steering(channels, enhancer, loading)
    return apply_weights(steer.weights, channels), steer


def beamform(channels: np.ndarray, enhancer: VoiceEnhancer, loading: float,
             dereverberation: DereverberationConfig | None = None) -> np.ndarray:
    """The one channel of :func:`front_end`."""
    return front_end(channels, enhancer, loading, dereverberation)[0]
