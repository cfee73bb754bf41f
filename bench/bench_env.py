"""Throughput of the vectorised training environment (simulated steps and decisions per second).

Usage: python bench/bench_env.py [--envs 1024] [--seconds 10]
"""

from __future__ import annotations

import argparse
import json
import resource
import time

import numpy as np

from mind.homeostasis import Homeostasis
from mind.personality import load_personality
from mind.policy.agent import DQNPolicy
from mind.policy.config import load_policy_config
from mind.policy.training.baselines import HomeostaticRule
from mind.policy.training.env import VecHomeostasisEnv


def measure(policy, envs: int, seconds: float) -> dict:
    """Run the env under ``policy`` for about ``seconds``; count steps and decisions."""
    h = Homeostasis(load_personality())
    env = VecHomeostasisEnv(h, load_policy_config().env, envs, seed=0)
    env.act(np.arange(envs), policy(env.observe()))
    ticks0, decisions = env.ticks, 0
    start = time.perf_counter()
    while time.perf_counter() - start < seconds:
        d = env.advance()
        decisions += len(d.idx)
        env.act(d.idx, policy(d.decide_obs))
    wall = time.perf_counter() - start
    steps = (env.ticks - ticks0) * envs  # every tick advances every env by one step
    return {"envs": envs, "wall_s": round(wall, 2), "decisions_per_s": round(decisions / wall),
            "steps_per_s": round(steps / wall)}


def main() -> None:
    """Print one JSON line per policy."""
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--envs", type=int, default=1024)
    parser.add_argument("--seconds", type=float, default=10.0)
    args = parser.parse_args()
    h = Homeostasis(load_personality())
    for name, policy in (("homeostatic_rule", HomeostaticRule(h)), ("dqn", DQNPolicy.load())):
        print(json.dumps({"policy": name, **measure(policy, args.envs, args.seconds)}))
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(json.dumps({"peak_rss_mb": round(peak)}))


if __name__ == "__main__":
    main()
