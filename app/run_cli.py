"""``companion run SCENARIO``: a headless household run with its report.

Handlers import their heavy modules when called, so that ``companion --help`` stays fast.
"""

from __future__ import annotations

import argparse
import json
import os
from pathlib import Path

from app.core.cli_args import integer, real


def add_commands(sub: argparse._SubParsersAction) -> None:
    """Register ``run``."""
    p = sub.add_parser("run", help="run a household scenario with the behaviour tree",
                       description="Run a household scenario (worlds/*.yaml) headless: the DQN "
                       "picks actions, the skills act in PyBullet. Writes events.jsonl, "
                       "timeline.csv, dialogue.jsonl, metrics.json, plots/, frames/ and "
                       "tree.txt into --out.")
    p.add_argument("scenario", type=Path, help="scenario YAML file")
    p.add_argument("--duration", type=real(above=0),
                   help="simulated seconds (default: the scenario's)")
    p.add_argument("--seed", type=integer(0), help="seed (default: the scenario's)")
    p.add_argument("--out", type=Path, help="run folder (default: runs/<scenario name>)")
    p.add_argument("--gui", action="store_true", help="open the PyBullet window")
    p.add_argument("--policy", type=Path, help="policy file (default: the shipped DQN)")
    p.add_argument("--behaviour", type=Path,
                   help="YAML overriding app/defaults/behaviour.yaml")
    p.add_argument("--audio", action="store_true",
                   help="also speak every sentence into audio/NNNN.wav (needs espeak-ng, "
                   "`make tts`)")
    p.add_argument("--json", action="store_true", help="print the metrics as one JSON object")
    p.add_argument("--no-progress", action="store_true", help="hide the progress bar")
    p.set_defaults(func=run_command)


def run_command(args: argparse.Namespace) -> int:
    """Handler of ``companion run``."""
    from app.core.errors import UserError
    from app.run import run_scenario
    from app.sim.scenario import load_scenario

    scenario = load_scenario(args.scenario)
    update: dict = {}
    if args.duration is not None:
        update["duration"] = args.duration
    if args.seed is not None:
        update["seed"] = args.seed
    scenario = scenario.model_copy(update=update)
    if args.gui and not os.environ.get("DISPLAY"):
        raise UserError("--gui needs a display (DISPLAY is not set); run headless without it")
    out = args.out or Path("runs") / scenario.name
    metrics = run_scenario(scenario, out, gui=args.gui, progress=not args.no_progress,
                           policy_path=args.policy, behaviour_config=args.behaviour,
                           audio=args.audio)
    if args.json:
        print(json.dumps(metrics))
    else:
        print(f"run folder: {out}")
        for key in ("duration_s", "rsr", "mood_positive_share", "preemptions",
                    "sentences_said", "camera_frames", "wall_s", "peak_rss_mb"):
            print(f"  {key:20s} {metrics[key]}")
        print(f"  {'actions':20s} {metrics['actions_started']}")
        print(f"  {'skill success':20s} {metrics['skill_success_rate']}")
    return 0
