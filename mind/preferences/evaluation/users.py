"""Simulated users: each has a hidden taste per action, and reacts to what the robot does.

A user who is present when an action ends reacts with probability ``react_prob``: praise
or scolding drawn from the ``liked``, ``disliked`` or ``neutral`` chances of their taste for
that action. Actions listed as ``unseen`` (the robot away charging, resting, standing by)
draw a reaction only from users who like or dislike them.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mind.personality import ACTIONS
from mind.preferences.config import SimulatedUsers

LIKE, NEUTRAL, DISLIKE = 1, 0, -1


@dataclass
class Population:
    """``kind[i]``: user i's type; ``taste[i, a]``: +1 likes, -1 dislikes, 0 neither."""

    kind: np.ndarray
    taste: np.ndarray
    praise: np.ndarray     # (N, actions): chance of praise when reacting
    scold: np.ndarray      # (N, actions): chance of scolding when reacting


def sample_population(cfg: SimulatedUsers, n: int, rng: np.random.Generator) -> Population:
    """``n`` users whose types follow the configured shares (rounded, then shuffled)."""
    names = list(cfg.types)
    counts = np.floor(np.array([cfg.types[k].share for k in names]) * n).astype(int)
    counts[np.argmax([cfg.types[k].share for k in names])] += n - counts.sum()
    kind = rng.permutation(np.repeat(np.array(names), counts))
    taste = np.zeros((n, len(ACTIONS)), int)
    for name, t in cfg.types.items():
        rows = kind == name
        for a in t.likes:
            taste[rows, ACTIONS.index(a)] = LIKE
        for a in t.dislikes:
            taste[rows, ACTIONS.index(a)] = DISLIKE
    unseen = np.isin(ACTIONS, cfg.unseen)[None, :] & (taste == NEUTRAL)
    praise = np.select([taste == LIKE, taste == DISLIKE], [cfg.liked.praise, cfg.disliked.praise],
                       cfg.neutral.praise)
    scold = np.select([taste == LIKE, taste == DISLIKE], [cfg.liked.scold, cfg.disliked.scold],
                      cfg.neutral.scold)
    return Population(kind, taste, np.where(unseen, 0.0, praise), np.where(unseen, 0.0, scold))


def react(pop: Population, users: np.ndarray, actions: np.ndarray, present: np.ndarray,
          react_prob: float, rng: np.random.Generator) -> np.ndarray:
    """Feedback (+1, -1 or 0) of ``users`` to the ``actions`` that just ended."""
    u, v = rng.random(len(users)), rng.random(len(users))
    reacts = present & (u < react_prob)
    praise, scold = pop.praise[users, actions], pop.scold[users, actions]
    return np.where(reacts & (v < praise), 1, np.where(reacts & (v >= 1 - scold), -1, 0))
