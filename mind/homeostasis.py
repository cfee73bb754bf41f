"""The homeostasis model of thesis §3.2: drives, stimuli, motivations, reward, security, mood.

Pure and step-based: every function takes arrays whose last axis holds the six drives
(or motivations, or three stimuli), so one robot (shape ``(6,)``) and a batch of
training episodes (shape ``(N, 6)``) run through the same code. One call of
:meth:`Homeostasis.step` advances one simulated step.
"""

from __future__ import annotations

import numpy as np

from mind.personality import ACTIONS, DRIVES, MOTIVATIONS, STAND_BY, STIMULI, Personality

ArrayLike = np.ndarray | float | int


class Homeostasis:
    """Equations 3.1-3.7 and 4.1 with the numbers of one :class:`Personality`."""

    def __init__(self, personality: Personality) -> None:
        self.personality = p = personality
        growth = [p.drives[d] for d in DRIVES]
        self.exponential = np.array([g.growth == "exponential" for g in growth])
        self.rate = np.array([g.rate or 0.0 for g in growth])
        self.tau = np.array([g.tau or np.inf for g in growth])

        effects = [p.actions[a] for a in ACTIONS]
        self.duration = np.array([e.duration for e in effects], dtype=np.int64)
        self.target = np.array([DRIVES.index(e.drive) if e.drive else -1 for e in effects])
        # relief[a, i]: how much action a lowers drive i in each of its steps (eq. 3.2 spread
        # evenly over the action's duration).
        self.relief = np.zeros((len(ACTIONS), len(DRIVES)))
        for a, e in enumerate(effects):
            if e.drive:
                self.relief[a, DRIVES.index(e.drive)] = e.decrease / e.duration
        # drifts[a, i]: whether drive i keeps growing while action a runs. Everything grows
        # during stand-by; during an action, the drives marked `grows_during_actions` do,
        # except the one the action is satisfying.
        busy = np.array([g.grows_during_actions for g in growth])
        self.drifts = np.array([np.ones(len(DRIVES), bool) if a == STAND_BY
                                else busy & (np.arange(len(DRIVES)) != self.target[a])
                                for a in range(len(ACTIONS))])

        # f_st of Table 4.3 as m = d + st @ gain + bias.
        self.stimulus_gain = np.zeros((len(STIMULI), len(MOTIVATIONS)))
        self.stimulus_bias = np.zeros(len(MOTIVATIONS))
        for m, effects_of_m in p.stimulus_effects.items():
            i = MOTIVATIONS.index(m)
            for st, eff in effects_of_m.items():
                j = STIMULI.index(st)
                if eff.when == "active":
                    self.stimulus_gain[j, i] += eff.weight
                else:
                    self.stimulus_gain[j, i] -= eff.weight
                    self.stimulus_bias[i] += eff.weight

        self.lower = np.array([p.desired_ranges[m][0] for m in MOTIVATIONS])
        self.upper = np.array([p.desired_ranges[m][1] for m in MOTIVATIONS])
        self.mood_weights = np.array([p.mood.drive_weights[d] for d in DRIVES])

    # -- drives ---------------------------------------------------------------------------
    def grow(self, drives: np.ndarray, steps: ArrayLike = 1) -> np.ndarray:
        """Drives after ``steps`` steps of growth alone (eq. 3.1 with Table 4.1), clipped to 1."""
        d = np.asarray(drives, dtype=np.float64)
        n = np.asarray(steps, dtype=np.float64)[..., None] if np.ndim(steps) else steps
        exp_growth = (1.0 + d) * np.exp(n / self.tau) - 1.0
        lin_growth = d + n * self.rate
        return np.minimum(np.where(self.exponential, exp_growth, lin_growth), 1.0)

    def step(self, drives: np.ndarray, action: ArrayLike, relieve: ArrayLike = True
             ) -> np.ndarray:
        """Drives after one step during which ``action`` (an index into ACTIONS) runs.
        ``relieve`` false means the action is under way but not yet satisfying its drive
        (the robot still drives to the dock, say): growth as during the action, no relief."""
        d = np.asarray(drives, dtype=np.float64)
        a = np.asarray(action)
        d = np.where(self.drifts[a], self.grow(d), d)
        relief = self.relief[a] * np.asarray(relieve, dtype=np.float64)[..., None]
        return np.clip(d - relief, 0.0, 1.0)

    # -- motivations, reward, security ----------------------------------------------------
    def motivations(self, drives: np.ndarray, stimuli: np.ndarray) -> np.ndarray:
        """Eq. 3.4: each motivation is its drive plus the stimulus terms f_st of Table 4.3."""
        st = np.asarray(stimuli, dtype=np.float64)
        return np.asarray(drives, dtype=np.float64) + st @ self.stimulus_gain + self.stimulus_bias

    def in_range(self, motivations: np.ndarray) -> np.ndarray:
        """Which motivations lie in their desired range."""
        m = np.asarray(motivations)
        return (m >= self.lower) & (m <= self.upper)

    def reward(self, action: ArrayLike, before: np.ndarray, after: np.ndarray,
               external: ArrayLike = 0.0) -> np.ndarray:
        """Eq. 3.7: the internal reward of an action that moved the motivations from
        ``before`` to ``after``, plus the external feedback (+1, -1 or 0)."""
        p = self.personality.reward
        a = np.asarray(action)
        i = np.maximum(self.target[a], 0)[..., None]
        m = np.take_along_axis(np.asarray(after), i, axis=-1)[..., 0]
        m_prev = np.take_along_axis(np.asarray(before), i, axis=-1)[..., 0]
        low, high = self.lower[i[..., 0]], self.upper[i[..., 0]]
        ok = ((m >= low) & (m <= high)) | (m_prev > high)
        acting = np.where(ok, p.kappa * (1.0 + m - high), p.lambda_ * (1.0 - (m - high)))
        standing = np.where(self.in_range(after).sum(axis=-1) > p.nu, 1.0, -1.0)
        return np.where(a == STAND_BY, standing, acting) + external

    def secure(self, drives: np.ndarray) -> np.ndarray:
        """Eq. 4.1: se(t), true while every drive is below the secure threshold."""
        return np.all(np.asarray(drives) < self.personality.secure_threshold, axis=-1)

    # -- mood -----------------------------------------------------------------------------
    def mood_value(self, drives: np.ndarray, encouragement: ArrayLike,
                   emotion: ArrayLike = 0.0) -> np.ndarray:
        """Eq. 3.6: v_mood from the drives, encouragement (0/1) and the human's emotion
        (+1 happy, -1 sad, 0 none or unknown)."""
        p = self.personality.mood
        return (np.asarray(drives) @ self.mood_weights
                - p.encouragement_weight * np.asarray(encouragement)
                + p.emotion_weight * np.asarray(emotion))

    def mood_positive(self, value: ArrayLike) -> np.ndarray:
        """The mood is positive while v_mood stays at or below the threshold eta."""
        return np.asarray(value) <= self.personality.mood.threshold
