"""Choosing with preferences: the DQN's action values plus what the person likes, shielded.

A person's preference ``p_a`` for action ``a`` is a running average of the external
rewards (eq. 3.7's r_external: +1 praise, -1 scolding) that followed ``a``:
``p_a <- p_a + alpha (r - p_a)``. The robot then picks ``argmax_a Q(s, a) + beta p_a``: the
DQN's value of the action plus beta times the feedback it expects, with a larger beta for
what a person dislikes than for what they like (a scolding asks the robot to stop; praise
need not make it repeat an action for ever). Adaptation must never
cost safety, so an action other than the DQN's own choice is allowed only while no drive
could reach ``secure_threshold - margin`` before it ends (:func:`safe_actions`). Every
function works on batches (a leading axis of people or simulated users).
"""

from __future__ import annotations

import numpy as np

from mind.homeostasis import Homeostasis
from mind.preferences.config import AdaptationConfig


def learn(prefs: np.ndarray, rows: np.ndarray, actions: np.ndarray, feedback: np.ndarray,
          rate: float) -> None:
    """In place: row ``rows[k]`` of ``prefs`` (people, actions) moves its entry for
    ``actions[k]`` towards ``feedback[k]`` (+1, -1; 0 means none). Rows are distinct."""
    given = feedback != 0
    r, a = rows[given], actions[given]
    prefs[r, a] += rate * (feedback[given] - prefs[r, a])


def drive_bound(h: Homeostasis, drives: np.ndarray) -> np.ndarray:
    """An upper bound of each drive while each action runs, shape (N, actions, drives).

    A drive that grows during the action ends highest (eq. 3.1 over the action's duration);
    one that does not stays put; the drive the action relieves is at most where it starts
    or where growth minus the whole relief leaves it."""
    d = np.asarray(drives, float)[..., None, :]                       # (N, 1, D)
    grown = h.grow(d, h.duration)                                     # (N, A, D)
    bound = np.where(h.drifts, grown, d)
    target = h.target >= 0
    rows = np.flatnonzero(target)
    cols = h.target[rows]
    relieved = grown[..., rows, cols] - h.relief[rows, cols] * h.duration[rows]
    bound[..., rows, cols] = np.maximum(d[..., 0, cols], relieved)
    return bound


def safe_actions(h: Homeostasis, drives: np.ndarray, margin: float) -> np.ndarray:
    """(N, actions): the actions during which no drive can reach the secure threshold minus
    ``margin``."""
    limit = h.personality.secure_threshold - margin
    return (drive_bound(h, drives) < limit).all(axis=-1)


def adapted_actions(q: np.ndarray, prefs: np.ndarray, safe: np.ndarray,
                    weights: tuple[float, float]) -> np.ndarray:
    """The actions that maximise ``q + w prefs`` among the safe ones and the DQN's own
    choice (``argmax q``), which is always allowed; ``weights``: ``w`` for a disliked
    action (``prefs < 0``) and for a liked one."""
    own = q.argmax(axis=-1)
    allowed = safe.copy()
    allowed[np.arange(len(own)), own] = True
    disliked, liked = weights
    bonus = np.where(prefs < 0, disliked, liked) * prefs
    score = np.where(allowed, q + bonus, -np.inf)
    return score.argmax(axis=-1)


def choose(h: Homeostasis, q: np.ndarray, prefs: np.ndarray, drives: np.ndarray,
           cfg: AdaptationConfig) -> np.ndarray:
    """The adapted choice for a batch: :func:`adapted_actions` among the actions
    :func:`safe_actions` allows for these ``drives``, with ``cfg``'s margin and weights."""
    safe = safe_actions(h, drives, cfg.safety_margin)
    return adapted_actions(q, prefs, safe, cfg.weights)
