"""Baseline policies on the same environment: uniform random and the homeostatic rule."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from mind.homeostasis import Homeostasis
from mind.personality import MOTIVATIONS, STAND_BY


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
    its desired range, otherwise stand by.

    ``anticipation`` (motivation name -> amount) makes the rule serve a motivation once it
    comes within that amount of its upper bound instead of once it passes it; empty, it is
    the classic rule. The DQN's demonstrations may come from such an anticipating rule."""

    def __init__(self, homeostasis: Homeostasis,
                 anticipation: Mapping[str, float] | None = None) -> None:
        early = anticipation or {}
        self.upper = homeostasis.upper - np.array([early.get(m, 0.0) for m in MOTIVATIONS])
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
