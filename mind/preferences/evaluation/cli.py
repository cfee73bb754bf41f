"""``companion eval feedback``: how fast and how safely the robot adapts to simulated users.

Handlers import their heavy modules when called, so that ``companion --help`` stays fast.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from core.cli_args import integer, real, seed


def add_eval(sub: argparse._SubParsersAction) -> None:
    """Register ``eval feedback``."""
    p = sub.add_parser("feedback", help="adaptation to simulated users' feedback",
                       description="Run the shipped DQN in the abstract household with "
                       "simulated users who praise and scold by hidden tastes: without "
                       "adaptation, with it, and with it but no memory between sessions; "
                       "then households of two users with a table per person or one shared. "
                       "Writes metrics.json and learning curves (docs/feedback.md).")
    p.add_argument("--users", type=integer(1, 100_000), default=1000,
                   help="simulated users, one household each (default 1000)")
    p.add_argument("--seed", type=seed(), default=0, help="seed of households and users")
    p.add_argument("--hours", type=real(above=0, below=1000), default=16.0,
                   help="simulated hours per household (default 16)")
    p.add_argument("--session-hours", type=real(above=0, below=1000), default=4.0,
                   help="session length for the no-memory arm (default 4)")
    p.add_argument("--events", type=integer(1, 10_000), default=50,
                   help="feedback events after which the bars are measured (default 50)")
    p.add_argument("--config", type=Path, help="feedback YAML (over config/feedback.yaml)")
    p.add_argument("--out", type=Path, default=Path("runs/eval-feedback"),
                   help="folder for metrics.json and plots")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=run_eval)


def run_eval(args: argparse.Namespace) -> int:
    """Handler of ``companion eval feedback``."""
    from core.checkpoint import atomic_write_bytes
    from mind.homeostasis import Homeostasis
    from mind.personality import load_personality
    from mind.policy.agent import DQNPolicy
    from mind.policy.config import load_policy_config
    from mind.preferences.config import load_feedback_config
    from mind.preferences.evaluation.evaluate import run_arm, summarise
    from mind.preferences.evaluation.plots import learning_curves

    cfg = load_feedback_config(args.config)
    h = Homeostasis(load_personality())
    steps = round(args.hours * 3600)
    env_cfg = load_policy_config().env.model_copy(update={"episode_steps": steps})
    policy = DQNPolicy.load()
    session = round(args.session_hours * 3600)
    one = {mode: run_arm(mode, policy, h, env_cfg, cfg, args.users, args.seed, session)
           for mode in ("none", "adapt", "no_memory")}
    two = {mode: run_arm(mode, policy, h, env_cfg, cfg, args.users // 2, args.seed, session,
                         people=2) for mode in ("none", "adapt", "shared")}
    summary = summarise(one, args.events)
    summary.update(two_users=summarise(two, args.events), users=args.users, seed=args.seed,
                   hours=args.hours, session_hours=args.session_hours,
                   config=cfg.model_dump(mode="json"))
    args.out.mkdir(parents=True, exist_ok=True)
    atomic_write_bytes(args.out / "metrics.json", (json.dumps(summary, indent=2) + "\n").encode())
    plot = learning_curves(summary, args.out / "plots")
    if args.json:
        print(json.dumps(summary))
        return 0
    print(f"{args.users} simulated users, {args.hours:g} h each; shares once a user had "
          f"given {args.events} feedback events:")
    print(table(summary["arms"], "one user per household"))
    print(table(summary["two_users"]["arms"], "two users per household"))
    print(f"\nmetrics.json and {plot.name} in {args.out}")
    return 0


def table(arms: dict, title: str) -> str:
    """A Markdown table of the arms' figures."""
    lines = [f"\n{title}:", "| arm | RSR % | disliked share (without) | drop | liked share "
             "(without) | gain | internal reward / h |", "|---|---|---|---|---|---|---|"]
    for mode, r in arms.items():
        lines.append(f"| {mode} | {100 * r['rsr']:.3f} | {r['disliked_share']:.4f} "
                     f"({r['disliked_share_without']:.4f}) | {r['disliked_share_drop']:+.1%} "
                     f"| {r['liked_share']:.4f} ({r['liked_share_without']:.4f}) "
                     f"| {r['liked_share_gain']:+.1%} | {r['reward_per_hour']:.1f} |")
    return "\n".join(lines)
