"""``companion run SCENARIO``: a headless household run with its report; and ``companion
bench household``: runs of every shipped world over seeds, summarised.

Handlers import their heavy modules when called, so that ``companion --help`` stays fast.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from pathlib import Path

from app.tablet.cli import add_server_options
from core.cli_args import integer, real, seed
from core.limits import MAX_DURATION_S


def add_commands(sub: argparse._SubParsersAction) -> None:
    """Register ``run``."""
    p = sub.add_parser("run", help="run a household scenario with the behaviour tree",
                       description="Run a household scenario (worlds/*.yaml) headless: the DQN "
                       "picks actions, the skills act in PyBullet. Writes events.jsonl, "
                       "timeline.csv, dialogue.jsonl, metrics.json, plots/, frames/ and "
                       "tree.txt into --out.")
    p.add_argument("scenario", type=Path, help="scenario YAML file")
    p.add_argument("--duration", type=real(above=0, below=MAX_DURATION_S + 1e-9),
                   help="simulated seconds (default: the scenario's)")
    p.add_argument("--seed", type=seed(), help="seed (default: the scenario's)")
    p.add_argument("--loop", action="store_true",
                   help="play the people's timelines again every <scenario duration> s, "
                   "everyone back at their start (with a longer --duration: a soak)")
    p.add_argument("--out", type=Path,
                   help="run folder (default: runs/<scenario name>-<date>-<time>); a folder "
                   "holding an earlier run is refused unless --overwrite")
    p.add_argument("--overwrite", action="store_true",
                   help="replace the earlier run in --out (its files are deleted first)")
    p.add_argument("--gui", action="store_true", help="open the PyBullet window")
    p.add_argument("--policy", type=Path, help="policy file (default: the shipped DQN)")
    p.add_argument("--behaviour", type=Path,
                   help="YAML overriding config/behaviour.yaml")
    p.add_argument("--audio", action="store_true",
                   help="also speak the robot's sentences into audio/NNNN.wav and people's "
                   "lines into audio/people/line-NNNN.wav, each in its own voice (robot/voices/)")
    p.add_argument("--hearing", choices=("audio", "fast"), default="audio",
                   help="audio (default): people's voices are synthesised, carried through "
                   "the rooms and recognised; fast: audible lines are heard as said, from "
                   "the acoustics' levels alone (for sweeps; docs/speech.md)")
    p.add_argument("--faults", type=Path,
                   help="YAML of faults to inject (docs/reliability.md): the run reports "
                   "each one and the robot's recovery in metrics.json")
    p.add_argument("--memory", type=Path,
                   help="the household's memory of what its people like (docs/feedback.md; "
                   "default: runs/memory/<scenario name>.json beside the run folder)")
    p.add_argument("--no-memory", action="store_true",
                   help="learn from feedback during this run only: no memory read or kept")
    p.add_argument("--no-adaptation", action="store_true",
                   help="feedback is logged, but the DQN alone chooses")
    p.add_argument("--profile", action="store_true",
                   help="time the run's parts (simulation step, render, detect, models, "
                   "tree, writing): a table, and `profile` in metrics.json")
    p.add_argument("--tablet", action="store_true",
                   help="serve the robot's tablet and the live view of its mind during the "
                   "run (docs/tablet.md)")
    add_server_options(p)
    p.add_argument("--json", action="store_true", help="print the metrics as one JSON object")
    p.add_argument("--no-progress", action="store_true", help="hide the progress bar")
    p.set_defaults(func=run_command)


def add_bench(sub: argparse._SubParsersAction) -> None:
    """Register ``bench household``."""
    p = sub.add_parser("household", help="every shipped world over seeds: interaction metrics",
                       description="Run every shipped world for its own duration, and the "
                       "nursing home for --long seconds, once per seed (each a `companion "
                       "run` in its own process; complete runs in --out are reused), and "
                       "print the mean and range of each interaction metric.")
    p.add_argument("--seeds", type=seed(), nargs="+", default=[0, 1, 2])
    p.add_argument("--worlds", nargs="+", default=None,
                   help="worlds/NAME.yaml to run (default: the six shipped worlds)")
    p.add_argument("--long", type=integer(0, int(MAX_DURATION_S)), default=3600,
                   help="seconds of the long nursing-home run (0: none; default 3600)")
    p.add_argument("--jobs", type=integer(1, 64), default=1, help="runs at a time")
    p.add_argument("--out", type=Path, default=Path("runs/bench-household"))
    p.add_argument("--docs", type=Path, help="write the table into this Markdown file "
                   "(between its bench markers), e.g. docs/BENCHMARKS.md")
    p.add_argument("--json", action="store_true", help="print the rows and summary as JSON")
    p.set_defaults(func=bench_command)


def bench_command(args: argparse.Namespace) -> int:
    """Handler of ``companion bench household``."""
    from app.household_bench import WORLDS, bench, plan, summarise, table, write_docs

    runs = plan(args.worlds or WORLDS, args.seeds, args.long)
    rows = bench(runs, args.out, args.jobs)
    summary = summarise(rows)
    text = table(summary, args.seeds)
    if args.docs:
        write_docs(text, args.docs, "companion bench household " + " ".join(sys.argv[3:]))
    print(json.dumps({"runs": rows, "summary": summary}) if args.json else text)
    return 0


def run_command(args: argparse.Namespace) -> int:
    """Handler of ``companion run``."""
    from app.faults import load_faults
    from app.run import RunOptions, prepare_scenario, run_scenario
    from app.tablet.cli import tablet_serving
    from core.errors import UserError
    from core.profiling import profile_table
    from core.run_folder import default_folder
    from core.signals import status_of

    scenario = prepare_scenario(args.scenario, duration=args.duration, seed=args.seed,
                                loop=args.loop)
    if args.gui and not os.environ.get("DISPLAY"):
        raise UserError("--gui needs a display (DISPLAY is not set); run headless without it")
    out = args.out or default_folder(Path("runs"), scenario.name)
    faults = load_faults(args.faults) if args.faults else None
    memory = None if args.no_memory or args.no_adaptation else (
        args.memory or out.parent / "memory" / f"{scenario.name}.json")
    with tablet_serving(args) as tablet:   # None without --tablet
        options = RunOptions(gui=args.gui, policy_path=args.policy,
                             behaviour_config=args.behaviour, audio=args.audio, faults=faults,
                             memory=memory, adapt=not args.no_adaptation,
                             profile=args.profile, tablet=tablet, hearing=args.hearing)
        metrics = run_scenario(scenario, out, options, progress=not args.no_progress,
                               overwrite=args.overwrite)
    status = status_of(metrics["interrupted_by"])
    if args.json:
        print(json.dumps(metrics))
    else:
        print(f"run folder: {out}")
        if metrics["interrupted"]:
            print(f"  INTERRUPTED by {metrics['interrupted_by']} at "
                  f"{metrics['duration_s']:.1f} of {scenario.duration:g} simulated s")
        for key in ("duration_s", "rsr", "mood_positive_share", "preemptions",
                    "sentences_said", "lines_said", "lines_heard", "lines_unclear",
                    "asked_again", "speech_wer", "lines_answered", "lines_replied",
                    "answer_latency_s_median", "lines_responded", "lines_ignored",
                    "voices_not_made_out", "voices_approached", "dont_know_answers",
                    "find_people_tries",
                    "find_people_found", "questions_asked", "questions_grounded",
                    "camera_frames", "wall_s", "peak_rss_mb"):
            print(f"  {key:24s} {metrics[key]}")
        print(f"  {'actions':24s} {metrics['actions_started']}")
        print(f"  {'skill success':24s} {metrics['skill_success_rate']}")
        if "profile" in metrics:
            print(profile_table(metrics["profile"]))
    return status
