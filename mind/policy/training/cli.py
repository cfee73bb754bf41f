"""`companion train policy` and `companion eval policy`.

Handlers import their heavy modules when called, so that ``companion --help`` stays fast.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from core.cli_args import integer, seed
from core.interrupts import training_command
from mind.policy.config import DEFAULT_POLICY

MODELS_DIR = DEFAULT_POLICY.parent
SHIPPED_LOG = MODELS_DIR / "policy_train_log.csv"


def add_train(sub: argparse._SubParsersAction) -> None:
    """Register ``train policy``."""
    p = sub.add_parser("policy", help="train the Dueling Double DQN decision maker",
                       description="Train the Dueling Double DQN on the abstract household. "
                       "Writes checkpoint.pt (resumable), train_log.csv, plots and policy.pt "
                       "into --out.")
    p.add_argument("--config", type=Path, help="policy YAML overriding config/policy.yaml")
    p.add_argument("--personality", type=Path, help="personality YAML overriding the thesis's")
    p.add_argument("--out", type=Path, default=Path("runs/train-policy"), help="run folder")
    p.add_argument("--resume", action="store_true", help="continue the checkpoint in --out "
                   "with the run's own resolved_config.yaml")
    p.add_argument("--export", type=Path,
                   help="also copy the trained policy here (e.g. assets/models/policy.pt)")
    p.add_argument("--no-progress", action="store_true", help="hide the progress bar")
    p.set_defaults(func=run_train)


def add_eval(sub: argparse._SubParsersAction) -> None:
    """Register ``eval policy``."""
    p = sub.add_parser("policy", help="compare the DQN with the random and homeostatic-rule "
                       "baselines", description="Run seeded test episodes for the trained DQN, "
                       "a random policy and the homeostatic rule; print RSR, reward, action "
                       "histogram and time above the secure threshold; save plots.")
    p.add_argument("--policy", type=Path, default=DEFAULT_POLICY, help="policy file to test")
    p.add_argument("--config", type=Path, help="policy YAML (its env section is used)")
    p.add_argument("--personality", type=Path, help="personality YAML")
    p.add_argument("--episodes", type=integer(1, 100_000), default=100,
                   help="test episodes (default 100)")
    p.add_argument("--seed", type=seed(), default=0, help="seed of the test episodes")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--demonstrator", action="store_true",
                   help="also test the rule that demonstrated to the DQN in training: the "
                   "homeostatic rule with the --config's train.demo_anticipation")
    p.add_argument("--out", type=Path, default=Path("runs/eval-policy"),
                   help="folder for metrics.json and plots")
    p.add_argument("--train-log", type=Path, default=SHIPPED_LOG,
                   help="training log to plot (default: the shipped policy's)")
    p.set_defaults(func=run_eval)


@training_command("policy")
def run_train(args: argparse.Namespace) -> int:
    """Handler of ``companion train policy``."""
    from core.checkpoint import atomic_copy
    from core.run_config import config_for
    from mind.personality import load_personality
    from mind.policy.config import load_policy_config
    from mind.policy.training.plots import training_curves
    from mind.policy.training.train import PolicyRunConfig, train

    run = config_for(args, PolicyRunConfig, lambda: PolicyRunConfig(
        personality=load_personality(args.personality), policy=load_policy_config(args.config)),
        "config", "personality")
    summary = train(run.personality, run.policy, args.out, resume=args.resume,
                    progress=not args.no_progress)
    training_curves(args.out / "train_log.csv", args.out / "plots")
    if args.export:
        atomic_copy(args.out / "policy.pt", args.export)
    print(json.dumps(summary, indent=2))
    return 0


def run_eval(args: argparse.Namespace) -> int:
    """Handler of ``companion eval policy``."""
    from mind.homeostasis import Homeostasis
    from mind.personality import ACTIONS, load_personality
    from mind.policy.agent import DQNPolicy
    from mind.policy.config import load_policy_config
    from mind.policy.training.baselines import HomeostaticRule, RandomPolicy
    from mind.policy.training.evaluate import paired_gain, run_episodes, summarise
    from mind.policy.training.plots import episode_figures, training_curves

    homeostasis = Homeostasis(load_personality(args.personality))
    cfg = load_policy_config(args.config)
    policies = {"dqn": DQNPolicy.load(args.policy),
                "random": RandomPolicy(len(ACTIONS), seed=args.seed),
                "homeostatic_rule": HomeostaticRule(homeostasis)}
    if args.demonstrator:
        policies["demonstrator"] = HomeostaticRule(homeostasis, cfg.train.demo_anticipation)
    results, trace, dqn_episodes = {}, None, None
    for name, policy in policies.items():
        episodes, tr = run_episodes(policy, homeostasis, cfg.env, args.episodes, args.seed,
                                    trace=name == "dqn")
        results[name] = summarise(episodes)
        if name == "dqn":  # first in the dict: the others are compared with it
            dqn_episodes = episodes
        else:
            results[name]["dqn_reward_gain"] = paired_gain(dqn_episodes, episodes)
        trace = trace or tr
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "metrics.json").write_text(json.dumps(results, indent=2))
    plots = episode_figures(trace, homeostasis.personality.mood.threshold, args.out / "plots")
    if args.train_log and args.train_log.is_file():
        plots += training_curves(args.train_log, args.out / "plots")
    if args.json:
        print(json.dumps(results))
    else:
        print(format_table(results))
        print(f"\nmetrics and {len(plots)} plots in {args.out}")
    return 0


def format_table(results: dict[str, dict]) -> str:
    """A plain-text comparison table of the evaluated policies."""
    from mind.personality import ACTIONS, DRIVES

    names = list(results)
    rows = [("RSR (%)", [f"{r['rsr'] * 100:.3f}" for r in results.values()]),
            ("worst episode RSR (%)", [f"{r['rsr_min'] * 100:.3f}" for r in results.values()]),
            ("mean episode reward", [f"{r['mean_reward']:.1f}" for r in results.values()]),
            ("DQN reward minus this", [gain_text(r.get("dqn_reward_gain"))
                                       for r in results.values()])]
    for a in ACTIONS:
        rows.append((f"decisions: {a}", [str(r["action_histogram"][a]) for r in
                                         results.values()]))
    for d in DRIVES:
        rows.append((f"time {d} >= 0.9 (%)",
                     [f"{r['time_above_threshold'][d] * 100:.3f}" for r in results.values()]))
    width = max(len(label) for label, _ in rows) + 2
    lines = [" " * width + "".join(f"{n:>18}" for n in names)]
    lines += [label.ljust(width) + "".join(f"{v:>18}" for v in vals) for label, vals in rows]
    return "\n".join(lines)


def gain_text(gain: dict | None) -> str:
    """``mean ± standard error`` of a paired reward difference, or blank for the DQN."""
    return "" if gain is None else f"{gain['mean']:+.1f} ± {gain['stderr']:.1f}"
