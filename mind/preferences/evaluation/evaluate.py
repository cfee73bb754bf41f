"""Adapting to simulated users in the abstract household (the policy's training env).

Each household has one simulated user with hidden tastes (:mod:`.users`), or two for the
shared-table ablation. The robot runs
the shipped DQN; with adaptation it learns the user's preferences from their feedback and
chooses with them (:mod:`mind.preferences.adaptation`). Every arm replays the same
seeded households and users, so arms are paired. Time is counted per user, by the user's
taste for the running action and by how many feedback events the user had given so far:
the learning curves and the bars come from that count.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from mind.homeostasis import Homeostasis
from mind.policy.agent import DQNPolicy
from mind.policy.config import EnvConfig
from mind.policy.training.env import VecHomeostasisEnv
from mind.preferences.adaptation import choose, learn
from mind.preferences.config import FeedbackConfig
from mind.preferences.evaluation.users import DISLIKE, LIKE, react, sample_population

MODES = ("none", "adapt", "no_memory", "shared")
# none: the DQN alone; adapt: each user's preferences learnt and kept; no_memory: learnt,
# but forgotten whenever a new session starts (a robot without --memory, every day anew);
# shared: one table for the whole household, whoever gave the feedback.
BIN = 10     # feedback events per learning-curve bin
BINS = 10    # bins 0-9, 10-19, ..., 90 and more


@dataclass
class Arm:
    """One arm's record. ``time[user, bin, taste + 1]``: steps the robot spent on actions the
    user dislikes (taste -1), neither (0) or likes (+1), by the bin of the user's feedback
    count at the time."""

    mode: str
    kind: np.ndarray          # each user's type
    taste: np.ndarray         # (users, actions)
    time: np.ndarray
    feedback: np.ndarray      # feedback events each user gave
    secure_steps: int = 0
    steps: int = 0
    reward: float = 0.0       # internal reward (eq. 3.7 without r_external), all episodes


def run_arm(mode: str, policy: DQNPolicy, h: Homeostasis, env_cfg: EnvConfig,
            cfg: FeedbackConfig, households: int, seed: int, session_steps: int,
            people: int = 1) -> Arm:
    """One episode (``env_cfg.episode_steps``) in each of ``households`` seeded households
    of ``people`` users (1 or 2). With two, whoever arrives is one of them at random; the
    robot knows who, and a user's time counts while they are present. ``shared`` keeps one
    preference table per household instead of one per person."""
    users = households * people
    pop = sample_population(cfg.simulated_users, users, np.random.default_rng(seed))
    env, rng = VecHomeostasisEnv(h, env_cfg, households, seed), np.random.default_rng(seed + 1)
    prefs = np.zeros((households if mode == "shared" else users, len(pop.praise[0])))
    arm = Arm(mode, pop.kind, pop.taste, np.zeros((users, BINS, 3)), np.zeros(users, int))
    who = np.arange(households) * people      # the user present, or the last one present
    was_present = env.human.copy()
    done = np.zeros(households, bool)
    adapt = cfg.adaptation

    def rows(idx: np.ndarray) -> np.ndarray:
        return idx if mode == "shared" else who[idx]

    def decide(idx: np.ndarray, obs: np.ndarray) -> np.ndarray:
        q = policy.q_values(obs)
        if mode == "none" or done[idx].all():
            return q.argmax(axis=-1)
        return choose(h, q, prefs[rows(idx)], env.drives[idx], adapt)

    env.act(np.arange(households), decide(np.arange(households), env.observe()))
    while not done.all():
        d = env.advance()
        for i, stats in zip(d.ended, d.episodes, strict=True):
            if not done[i]:
                arm.secure_steps += round(stats["rsr"] * stats["steps"])
                arm.steps += stats["steps"]
                arm.reward += stats["return"]
        live = ~done[d.idx]
        idx, act, present = d.idx[live], d.action[live], env.human[d.idx[live]]
        if people > 1:   # someone came since the last decision: one of them, at random
            came = present & ~was_present[idx]
            who[idx[came]] = idx[came] * people + rng.integers(0, people, int(came.sum()))
        was_present[d.idx] = env.human[d.idx]
        user = who[idx]
        seen = present if people > 1 else np.ones(len(idx), bool)
        bins = np.minimum(arm.feedback[user] // BIN, BINS - 1)
        np.add.at(arm.time, (user[seen], bins[seen], pop.taste[user, act][seen] + 1),
                  h.duration[act[seen]])
        fb = react(pop, user, act, present, cfg.simulated_users.react_prob, rng)
        arm.feedback[user] += fb != 0
        if mode != "none":
            learn(prefs, rows(idx), act, fb, adapt.learning_rate)
        if mode == "no_memory":   # a session began during the action: a blank memory
            began = env.t[idx] // session_steps != (env.t[idx] - h.duration[act]) // session_steps
            prefs[rows(idx[began])] = 0.0
        done[d.ended] = True
        env.act(d.idx, decide(d.idx, d.decide_obs))   # finished households idle on, unrecorded
    return arm


def share_after(arm: Arm, users: np.ndarray, taste: int, events: int) -> float:
    """The share of ``users``' time on actions of ``taste`` once each had given ``events``
    feedback events (NaN when there is no such time)."""
    t = arm.time[users][:, events // BIN:].sum(axis=(0, 1))
    return float(t[taste + 1] / t.sum()) if t.sum() else float("nan")


def curve(arm: Arm, users: np.ndarray, taste: int) -> list[float | None]:
    """Per feedback-count bin: the share of ``users``' time on actions of ``taste``."""
    t = arm.time[users].sum(axis=0)
    return [round(float(b[taste + 1] / b.sum()), 5) if b.sum() else None for b in t]


def summarise(arms: dict[str, Arm], events: int) -> dict[str, Any]:
    """The bars' figures, each arm against ``none`` (the DQN alone, same households).

    ``disliked_share_drop``: the relative drop of the share of time on disliked actions,
    over the users who dislike something and gave ``events`` feedback events, from then
    on, against the same users' share over the whole run without adaptation.
    ``liked_share_gain``: the relative rise of liked actions, likewise. ``rsr``: secure steps
    over all steps. ``curves``: disliked and liked shares per feedback-count bin and type."""
    base = arms["none"]
    out: dict[str, Any] = {"events": events, "arms": {}}
    for mode, arm in arms.items():
        row: dict[str, Any] = {
            "rsr": arm.secure_steps / arm.steps,
            "reward_per_hour": arm.reward / arm.steps * 3600,
            "users": len(arm.kind),
            "median_feedback_events": float(np.median(arm.feedback)),
            "users_past_events": int((arm.feedback >= events).sum()),
            "curves": {kind: {"disliked": curve(arm, np.flatnonzero(arm.kind == kind), DISLIKE),
                              "liked": curve(arm, np.flatnonzero(arm.kind == kind), LIKE)}
                       for kind in sorted(set(arm.kind.tolist()))},
        }
        for name, taste in (("disliked", DISLIKE), ("liked", LIKE)):
            who = np.flatnonzero((arm.taste == taste).any(axis=1) & (arm.feedback >= events))
            row[f"{name}_users"] = len(who)
            row[f"{name}_share"] = share_after(arm, who, taste, events)
            row[f"{name}_share_without"] = share_after(base, who, taste, 0)
        row["disliked_share_drop"] = 1.0 - row["disliked_share"] / row["disliked_share_without"]
        row["liked_share_gain"] = row["liked_share"] / row["liked_share_without"] - 1.0
        out["arms"][mode] = row
    adapt = out["arms"].get("adapt", out["arms"]["none"])
    out.update({k: adapt[k] for k in ("disliked_share_drop", "liked_share_gain", "rsr")})
    return out
