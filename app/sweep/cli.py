"""``companion sweep SPEC.yaml``: household runs over worlds, seeds and options, on Ray.

Handlers import their heavy modules when called, so that ``companion --help`` stays fast.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from core.cli_args import real


def add_commands(sub: argparse._SubParsersAction) -> None:
    """Register ``sweep``."""
    p = sub.add_parser("sweep", help="many household runs on Ray, summarised",
                       description="Run every entry of a sweep spec (docs/sweeps.md) as its "
                       "own Ray task, skip those already complete in --out, and write "
                       "sweep.csv, summary.md and plots/ there.")
    p.add_argument("spec", type=Path, help="sweep spec YAML")
    p.add_argument("--out", type=Path, help="sweep folder (default: runs/sweep-<spec name>)")
    p.add_argument("--address", help="join a Ray cluster (`auto` or HOST:PORT; default: "
                   "start a local Ray on this machine's cores)")
    p.add_argument("--cpus-per-run", type=real(above=0, below=1025), default=1.0,
                   help="cores Ray reserves for each run (default 1)")
    p.add_argument("--worker-dir", type=Path,
                   help="on a cluster without a shared disk: where workers write their run "
                   "folders; the driver collects metrics.json and events.jsonl into --out")
    p.add_argument("--no-progress", action="store_true", help="hide the progress bar")
    p.set_defaults(func=run_sweep)


def run_sweep(args: argparse.Namespace) -> int:
    """Handler of ``companion sweep``: 0 when every run finished, 1 when one failed, 130 or
    143 when interrupted."""
    from app.sweep.report import write_report
    from app.sweep.runner import sweep
    from app.sweep.spec import load_sweep
    from core.signals import exit_status, signal_name

    spec, runs = load_sweep(args.spec)
    out = args.out or Path("runs") / f"sweep-{args.spec.stem}"
    rows, interrupt = sweep(runs, out, address=args.address, cpus_per_run=args.cpus_per_run,
                            worker_dir=args.worker_dir, progress=not args.no_progress)
    summary = write_report(rows, spec.checks, out,
                           signal_name(interrupt) if interrupt is not None else None)
    print(summary)
    print(f"sweep folder: {out} (sweep.csv, summary.md, plots/)")
    failed = [r for r in rows if r.get("error")]
    if failed:
        print(f"{len(failed)} of {len(rows)} runs failed (see summary.md)", file=sys.stderr)
    return exit_status(interrupt) if interrupt is not None else int(bool(failed))
