"""Parallel sweep against serial runs, side by side, on this machine.

    python bench/bench_sweep.py [--runs 8] [--duration 300] [--out runs/bench-sweep]

First ``--runs`` household runs of worlds/living_room.yaml (seeds 0..runs-1, ``--duration``
simulated s) one after the other as `companion run` processes; then the same entries as one
`companion sweep` on a local Ray (one run per core). Prints both wall times, their ratio,
each run's peak memory and the sweep driver's.
"""

from __future__ import annotations

import argparse
import json
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

from app.sweep.runner import sweep
from app.sweep.spec import Run

WORLD = Path(__file__).resolve().parents[1] / "worlds" / "living_room.yaml"


def main() -> None:
    """Run both ways and print the figures."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=8)
    parser.add_argument("--duration", type=float, default=300.0)
    parser.add_argument("--out", type=Path, default=Path("runs/bench-sweep"))
    args = parser.parse_args()
    t0 = time.perf_counter()
    serial_rss = []
    for seed in range(args.runs):
        folder = args.out / "serial" / f"seed{seed}"
        subprocess.run([sys.executable, "-m", "app.cli", "run", str(WORLD), "--out",
                        str(folder), "--overwrite", "--seed", str(seed), "--duration",
                        str(args.duration), "--no-progress"], check=True,
                       stdout=subprocess.DEVNULL)
        serial_rss.append(json.loads((folder / "metrics.json").read_text())["peak_rss_mb"])
    serial = time.perf_counter() - t0
    runs = [Run(str(WORLD), s, args.duration, None, None, None) for s in range(args.runs)]
    parallel_out = args.out / f"sweep-{int(time.time())}"   # a new folder: nothing to skip
    t0 = time.perf_counter()
    rows, _ = sweep(runs, parallel_out, address=None, cpus_per_run=1.0, progress=False)
    parallel = time.perf_counter() - t0
    run_rss = [r["metrics"]["peak_rss_mb"] for r in rows if r.get("metrics")]
    print(f"{args.runs} runs of {args.duration:g} simulated s: serial {serial:.0f} s, "
          f"sweep {parallel:.0f} s, ratio {parallel / serial:.2f} "
          f"({len(run_rss)} of {args.runs} finished)")
    print(f"peak resident MB per run: serial median {statistics.median(serial_rss):.0f}, "
          f"in the sweep median {statistics.median(run_rss):.0f} (max {max(run_rss):.0f}); "
          f"sweep driver {resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024:.0f}")


if __name__ == "__main__":
    main()
