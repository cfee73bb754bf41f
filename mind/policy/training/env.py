"""A fast abstract household for training the policy: many episodes advanced step by step.

Drives follow :class:`mind.homeostasis.Homeostasis` exactly as on the robot; the three
stimuli follow simple stochastic models configured in ``env`` of the policy YAML: people
arrive and leave at random, `find_people` usually ends in front of someone, social actions
with a person present may earn encouragement, and motion heats the motors. Every env runs
its current action for the action's duration; a decision is needed when it ends.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from mind.homeostasis import Homeostasis
from mind.personality import ACTIONS, DRIVES, STIMULI
from mind.policy.config import EnvConfig

OVERHEAT, HUMAN, ENCOURAGEMENT = (STIMULI.index(s) for s in STIMULI)


@dataclass
class Decisions:
    """Envs whose action just ended: the finished transitions and what to decide on next."""

    idx: np.ndarray           # which envs
    obs: np.ndarray           # motivations when the finished action was chosen
    action: np.ndarray        # the finished action
    reward: np.ndarray        # eq. 3.7
    next_obs: np.ndarray      # motivations now (bootstrap target)
    decide_obs: np.ndarray    # motivations to decide on: next_obs, or a fresh episode's start
    terminal: np.ndarray      # the robot became insecure during the action (when terminating)
    became_insecure: np.ndarray  # secure when the action began, a drive reached the secure
                                 # threshold during it
    ended: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    episodes: list[dict] = field(default_factory=list)  # stats of those envs' episodes


@dataclass
class Trace:
    """Per-step record of env 0, for plots of one episode."""

    drives: list[np.ndarray] = field(default_factory=list)
    motivations: list[np.ndarray] = field(default_factory=list)
    stimuli: list[np.ndarray] = field(default_factory=list)
    action: list[int] = field(default_factory=list)
    mood: list[float] = field(default_factory=list)


class VecHomeostasisEnv:
    """``num_envs`` independent abstract episodes sharing one clock."""

    def __init__(self, homeostasis: Homeostasis, cfg: EnvConfig, num_envs: int,
                 seed: int) -> None:
        self.h, self.cfg, self.n = homeostasis, cfg, num_envs
        self.rng = np.random.default_rng(seed)
        self.heating = np.array([cfg.heat.heating.get(a, 0.0) for a in ACTIONS])
        self.cooling = np.array([cfg.heat.cooling.get(a, cfg.heat.other_cooling)
                                 for a in ACTIONS])
        self.encouraging = np.array([a in cfg.encouragement.after_actions for a in ACTIONS])
        self.finds = np.array([a == "find_people" for a in ACTIONS])
        self.trace: Trace | None = None
        self.ticks = 0  # steps taken by the shared clock
        n = num_envs
        self.drives = np.zeros((n, len(DRIVES)))
        self.human = np.zeros(n, dtype=bool)
        self.heat = np.zeros(n)
        self.encouraged_for = np.zeros(n, dtype=np.int64)
        self.action = np.zeros(n, dtype=np.int64)
        self.remaining = np.zeros(n, dtype=np.int64)
        self.obs_at_choice = np.zeros((n, len(DRIVES)))
        self.t = np.zeros(n, dtype=np.int64)
        self.secure_steps = np.zeros(n, dtype=np.int64)
        self.insecure_in_action = np.zeros(n, dtype=bool)
        self.secure_at_choice = np.ones(n, dtype=bool)
        self.high_steps = np.zeros((n, len(DRIVES)), dtype=np.int64)
        self.ep_return = np.zeros(n)
        self.ep_actions = np.zeros((n, len(ACTIONS)), dtype=np.int64)
        self.reset(np.arange(n))

    # -- state ----------------------------------------------------------------------------
    def stimuli(self) -> np.ndarray:
        """The (N, 3) binary stimuli: overheat, human present, encouragement."""
        st = np.zeros((self.n, len(STIMULI)))
        st[:, OVERHEAT] = self.heat >= self.cfg.heat.threshold
        st[:, HUMAN] = self.human
        st[:, ENCOURAGEMENT] = self.encouraged_for > 0
        return st

    def observe(self, idx: np.ndarray | None = None) -> np.ndarray:
        """Motivations (the policy's state) of the envs ``idx`` (all when None)."""
        m = self.h.motivations(self.drives, self.stimuli())
        return m if idx is None else m[idx]

    def reset(self, idx: np.ndarray) -> None:
        """Start fresh episodes in envs ``idx`` with random drives, people and heat."""
        k = len(idx)
        low, high = self.cfg.initial_drives
        self.drives[idx] = self.rng.uniform(low, high, size=(k, len(DRIVES)))
        self.human[idx] = self.rng.random(k) < 0.5
        self.heat[idx] = self.rng.uniform(*self.cfg.heat.initial, size=k)
        self.encouraged_for[idx] = 0
        self.remaining[idx] = 0
        self.t[idx] = 0
        self.secure_steps[idx] = 0
        self.high_steps[idx] = 0
        self.ep_return[idx] = 0.0
        self.ep_actions[idx] = 0

    def act(self, idx: np.ndarray, actions: np.ndarray) -> None:
        """Start ``actions`` in envs ``idx``; each runs for its duration in steps."""
        self.obs_at_choice[idx] = self.observe(idx)
        self.action[idx] = actions
        self.remaining[idx] = self.h.duration[actions]
        self.insecure_in_action[idx] = False
        self.secure_at_choice[idx] = self.h.secure(self.drives[idx])
        self.ep_actions[idx, actions] += 1

    # -- dynamics -------------------------------------------------------------------------
    def _tick(self) -> None:
        """Advance every env by one step."""
        a = self.action
        self.drives = self.h.step(self.drives, a)
        u = self.rng.random(self.n)
        p = self.cfg.people
        self.human = np.where(self.human, u >= p.leave_prob, u < p.arrive_prob)
        self.encouraged_for = np.maximum(self.encouraged_for - 1, 0)
        self.heat = np.clip(self.heat + self.heating[a] - self.cooling[a] * self.heat, 0, 1)
        self.t += 1
        self.ticks += 1
        self.remaining -= 1
        secure = self.h.secure(self.drives)
        self.secure_steps += secure
        self.insecure_in_action |= ~secure
        self.high_steps += self.drives >= self.h.personality.secure_threshold
        if self.trace is not None:
            self._record()

    def _record(self) -> None:
        st = self.stimuli()[0]
        tr = self.trace
        tr.drives.append(self.drives[0].copy())
        tr.motivations.append(self.h.motivations(self.drives[0], st))
        tr.stimuli.append(st)
        tr.action.append(int(self.action[0]))
        tr.mood.append(float(self.h.mood_value(self.drives[0], st[ENCOURAGEMENT])))

    def _outcomes(self, idx: np.ndarray) -> None:
        """Stimulus outcomes of the actions that just ended in envs ``idx``."""
        a = self.action[idx]
        found = self.finds[a] & (self.rng.random(len(idx)) < self.cfg.people.find_success_prob)
        self.human[idx] |= found
        enc = self.cfg.encouragement
        praised = (self.encouraging[a] & self.human[idx]
                   & (self.rng.random(len(idx)) < enc.prob))
        self.encouraged_for[idx[praised]] = enc.duration

    def advance(self) -> Decisions:
        """Step until at least one action ends; return those envs' transitions."""
        while True:
            self._tick()
            idx = np.flatnonzero(self.remaining <= 0)
            if len(idx):
                break
        self._outcomes(idx)
        next_obs = self.observe(idx)
        action = self.action[idx].copy()
        reward = self.h.reward(action, self.obs_at_choice[idx], next_obs)
        self.ep_return[idx] += reward
        insecure = self.insecure_in_action[idx]
        terminal = insecure & self.cfg.terminate_on_insecure
        out = Decisions(idx, self.obs_at_choice[idx].copy(), action, reward, next_obs,
                        next_obs.copy(), terminal, insecure & self.secure_at_choice[idx])
        ended = idx[(self.t[idx] >= self.cfg.episode_steps) | terminal]
        if len(ended):
            out.ended = ended
            out.episodes = [self.episode_stats(i) for i in ended]
            self.reset(ended)
            out.decide_obs[np.isin(idx, ended)] = self.observe(ended)
        return out

    STATE = ("drives", "human", "heat", "encouraged_for", "action", "remaining", "obs_at_choice",
             "t", "secure_steps", "insecure_in_action", "secure_at_choice", "high_steps",
             "ep_return", "ep_actions")

    def state_dict(self) -> dict:
        """Everything needed to continue these episodes exactly (arrays and the RNG)."""
        state = {k: getattr(self, k).copy() for k in self.STATE}
        state["rng"] = self.rng.bit_generator.state
        return state

    def load_state_dict(self, state: dict) -> None:
        """Restore from :meth:`state_dict`."""
        for k in self.STATE:
            setattr(self, k, state[k])
        self.rng.bit_generator.state = state["rng"]

    def episode_stats(self, i: int) -> dict:
        """Summary of env ``i``'s current episode."""
        steps = int(self.t[i])
        return {
            "steps": steps,
            "rsr": float(self.secure_steps[i] / max(steps, 1)),
            "return": float(self.ep_return[i]),
            "actions": {a: int(c) for a, c in zip(ACTIONS, self.ep_actions[i], strict=True)},
            "steps_above_threshold": {d: int(c) for d, c in
                                      zip(DRIVES, self.high_steps[i], strict=True)},
        }
