"""Seeded test episodes for the DQN and the baselines, summarised like thesis §4.1."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from mind.homeostasis import Homeostasis
from mind.personality import ACTIONS, DRIVES
from mind.policy.config import EnvConfig
from mind.policy.training.env import Trace, VecHomeostasisEnv

PolicyFn = Callable[[np.ndarray], np.ndarray]


def run_episodes(policy: PolicyFn, homeostasis: Homeostasis, cfg: EnvConfig, episodes: int,
                 seed: int, trace: bool = False) -> tuple[list[dict], Trace | None]:
    """Run ``episodes`` seeded episodes side by side; episode k always starts from the same
    state for a given seed, whatever the policy. Returns their stats and, when asked, the
    step-by-step trace of the first episode."""
    env = VecHomeostasisEnv(homeostasis, cfg, episodes, seed)
    if trace:
        env.trace = Trace()
    results: dict[int, dict] = {}
    recorded = None
    env.act(np.arange(episodes), policy(env.observe()))
    while len(results) < episodes:
        d = env.advance()
        for i, stats in zip(d.ended, d.episodes, strict=True):
            results.setdefault(int(i), stats)
        if env.trace is not None and 0 in d.ended:
            recorded, env.trace = env.trace, None
        env.act(d.idx, policy(d.decide_obs))
    return [results[i] for i in range(episodes)], recorded


def summarise(episodes: list[dict]) -> dict:
    """RSR, reward, action histogram and time above the secure threshold over episodes."""
    steps = sum(e["steps"] for e in episodes)
    returns = np.array([e["return"] for e in episodes])
    counts = {a: sum(e["actions"][a] for e in episodes) for a in ACTIONS}
    return {
        "episodes": len(episodes),
        "rsr": float(np.mean([e["rsr"] for e in episodes])),
        "rsr_min": float(np.min([e["rsr"] for e in episodes])),
        "mean_reward": float(returns.mean()),
        "reward_std": float(returns.std()),
        "action_histogram": counts,
        "time_above_threshold": {d: sum(e["steps_above_threshold"][d] for e in episodes) / steps
                                 for d in DRIVES},
    }


def paired_gain(episodes: list[dict], baseline: list[dict]) -> dict:
    """Mean and standard error of the per-episode reward of ``episodes`` minus that of
    ``baseline``, episode k of each having started from the same state."""
    gain = np.array([e["return"] - b["return"] for e, b in zip(episodes, baseline, strict=True)])
    stderr = gain.std(ddof=1) / np.sqrt(len(gain)) if len(gain) > 1 else float("nan")
    return {"mean": float(gain.mean()), "stderr": float(stderr)}
