"""One run of a sweep, as a Ray task executes it in its own worker process: a household
run (:func:`execute`) or a DQN training with its test (:func:`execute_training`)."""

from __future__ import annotations

import json
import resource
import time
from pathlib import Path
from typing import Any

from app.faults import load_faults
from app.run import RunOptions, prepare_scenario, run_scenario
from app.sweep.spec import Run, TrainRun
from core.checkpoint import atomic_write_bytes
from mind.homeostasis import Homeostasis
from mind.personality import load_personality
from mind.policy.agent import DQNPolicy
from mind.policy.config import load_policy_config
from mind.policy.training.baselines import HomeostaticRule
from mind.policy.training.evaluate import paired_gain, run_episodes, summarise
from mind.policy.training.train import train


def execute(run: Run, folder: Path, collect: bool, threads: int) -> dict[str, Any]:
    """Run ``run`` into ``folder`` (an earlier, unfinished attempt there is replaced) with
    the detector on ``threads`` CPU threads (the cores Ray gave the run), and return its
    metrics, and with ``collect`` the text of its ``events.jsonl`` (for a driver that does
    not share the worker's disk)."""
    scenario = prepare_scenario(Path(run.world), duration=run.duration, seed=run.seed,
                                personality=Path(run.personality) if run.personality else None)
    faults = load_faults(run.faults) if run.faults else None
    options = RunOptions(faults=faults, policy_path=Path(run.policy) if run.policy else None,
                         threads=threads, hearing=run.hearing)  # type: ignore[arg-type]
    metrics = run_scenario(scenario, folder, options, progress=False, overwrite=True,
                           tags={"sweep_key": run.key})
    events = (folder / "events.jsonl").read_text(encoding="utf-8") if collect else None
    return {"metrics": metrics, "events": events}


def execute_training(run: TrainRun, folder: Path) -> dict[str, Any]:
    """Train the DQN of ``run`` into ``folder`` (continuing an interrupted attempt there),
    test it and the homeostatic rule on the same seeded episodes, and write and return the
    figures as the training's ``metrics.json``."""
    personality = load_personality(Path(run.personality) if run.personality else None)
    cfg = load_policy_config(Path(run.config) if run.config else None)
    cfg = cfg.model_copy(update={"train": cfg.train.model_copy(update={"seed": run.seed})})
    start = time.perf_counter()
    train(personality, cfg, folder, resume=(folder / "checkpoint.pt").exists(), progress=False)
    homeostasis = Homeostasis(personality)
    episodes = {name: run_episodes(policy, homeostasis, cfg.env, run.episodes, run.eval_seed)[0]
                for name, policy in (("dqn", DQNPolicy.load(folder / "policy.pt")),
                                     ("rule", HomeostaticRule(homeostasis)))}
    dqn, rule = summarise(episodes["dqn"]), summarise(episodes["rule"])
    margin = paired_gain(episodes["dqn"], episodes["rule"])
    metrics = {"rsr": dqn["rsr"], "rsr_min": dqn["rsr_min"], "mean_reward": dqn["mean_reward"],
               "rule_rsr": rule["rsr"], "rule_mean_reward": rule["mean_reward"],
               "reward_margin": margin["mean"], "reward_margin_stderr": margin["stderr"],
               "interrupted": False, "wall_s": round(time.perf_counter() - start, 1),
               "peak_rss_mb": round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
                                    1),
               "sweep_key": run.key}
    atomic_write_bytes(folder / "metrics.json", json.dumps(metrics, indent=2).encode())
    return {"metrics": metrics, "events": None}
