"""Household runs: wall time, memory and RSR of full scenario runs with the behaviour tree.

Each scenario runs in its own process (peak memory is per run) through ``companion run``.
Usage: python bench/bench_household.py [--worlds living_room nursing_home ...]
       [--duration SECONDS] [--out runs/bench-household] [--json]

``--duration 1800`` on ``nursing_home`` is the 30-minute speed bar; the default durations
give the RSR figure compared with the abstract environment's (``companion eval policy``).
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

WORLDS = ("living_room", "nursing_home", "birthday_party", "low_battery_night")


def run_one(world: str, out: Path, duration: float | None) -> dict:
    """One ``companion run`` in a child process; its metrics plus wall and peak memory."""
    cmd = [sys.executable, "-m", "app.cli", "run", f"worlds/{world}.yaml", "--out", str(out),
           "--no-progress", "--json"]
    if duration is not None:
        cmd += ["--duration", str(duration)]
    start = time.perf_counter()
    done = subprocess.run(["/usr/bin/time", "-f", "%M", *cmd], capture_output=True, text=True,
                          check=True)
    wall = time.perf_counter() - start
    metrics = json.loads(done.stdout.strip().splitlines()[-1])
    peak_kb = int(done.stderr.strip().splitlines()[-1])
    return {"world": world, "sim_s": metrics["duration_s"], "wall_s": round(wall, 1),
            "realtime_factor": round(metrics["duration_s"] / wall, 1),
            "peak_rss_mb": round(peak_kb / 1024), "rsr": metrics["rsr"],
            "camera_frames": metrics["camera_frames"], "actions": metrics["actions_started"],
            "skill_success_rate": metrics["skill_success_rate"]}


def main() -> None:
    """Run the benchmark and print a table (or JSON)."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--worlds", nargs="+", default=list(WORLDS), choices=WORLDS)
    ap.add_argument("--duration", type=float, help="simulated seconds (default: each world's)")
    ap.add_argument("--out", type=Path, default=Path("runs/bench-household"))
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    rows = [run_one(w, args.out / w, args.duration) for w in args.worlds]
    steps = sum(r["sim_s"] for r in rows)
    pooled = sum(r["rsr"] * r["sim_s"] for r in rows) / steps
    summary = {"runs": rows, "pooled_rsr": pooled}
    if args.json:
        print(json.dumps(summary))
        return
    print(f"{'world':18s} {'sim s':>7s} {'wall s':>7s} {'x real':>6s} {'MB':>5s} "
          f"{'RSR %':>8s} {'frames':>6s}")
    for r in rows:
        print(f"{r['world']:18s} {r['sim_s']:7.0f} {r['wall_s']:7.1f} {r['realtime_factor']:6.1f}"
              f" {r['peak_rss_mb']:5d} {100 * r['rsr']:8.3f} {r['camera_frames']:6d}")
    print(f"pooled RSR {100 * pooled:.3f} %")


if __name__ == "__main__":
    main()
