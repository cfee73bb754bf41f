"""Baseline policies on the same environment: uniform random and the homeostatic rule."""

from __future__ import annotations

import numpy as np

from app.homeostasis import Homeostasis
from app.personality import STAND_BY


class RandomPolicy:
    """Picks each of the seven actions with equal probability."""

    def __init__(self, n_actions: int, seed: int) -> None:
        self.n_actions = n_actions
        self.rng = np.random.default_rng(seed)

    def __call__(self, motivations: np.ndarray) -> np.ndarray:
        """One random action per row of ``motivations``."""
        return self.rng.integers(0, self.n_actions, size=len(motivations))


class HomeostaticRule:
    """The classic rule (Cañamero; ROBEE): serve the strongest motivation once it rises above
    its desired range, otherwise stand by."""

    def __init__(self, homeostasis: Homeostasis) -> None:
        self.upper = homeostasis.upper
        # serves[i]: the action that lowers drive (and motivation) i
        self.serves = np.full(len(homeostasis.upper), STAND_BY)
        for a, target in enumerate(homeostasis.target):
            if target >= 0:
                self.serves[target] = a

    def __call__(self, motivations: np.ndarray) -> np.ndarray:
        """One action per row of ``motivations``."""
        m = np.asarray(motivations)
        strongest = m.argmax(axis=-1)
        over = np.take_along_axis(m > self.upper, strongest[..., None], axis=-1)[..., 0]
        return np.where(over, self.serves[strongest], STAND_BY)
