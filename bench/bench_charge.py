"""Docking from anywhere: the charge skill's approach (path to the pre-dock pose, then straight
in) from random free poses in each household, until the ``docked`` event or the skill's
``timeout_s``.

Each trial builds the world afresh (people at their scenario starts, the timeline playing),
puts the robot in a free cell drawn uniformly from the occupancy grid (a uniform point in that
cell, uniform yaw) and ticks only the approach subtree, without sensing.

Usage: python bench/bench_charge.py [--trials 100] [--seed 0] [--world NAME ...] [--json PATH]
"""

from __future__ import annotations

import argparse
import json
import math
import time
import zlib
from pathlib import Path
from typing import Any

import numpy as np
from py_trees.common import Status

from app.sim.navigation import Navigator
from app.sim.robot import wrap_angle
from app.sim.scenario import Scenario, load_scenario
from app.sim.simulation import Simulation
from behaviours.config import BehaviourConfig, load_behaviour_config
from behaviours.context import make_context
from behaviours.skills.charge import approach
from behaviours.ticking import SimulationTree

WORLDS = Path(__file__).resolve().parents[1] / "worlds"


def trial(scenario: Scenario, config: BehaviourConfig, rng: np.random.Generator,
          ) -> dict[str, Any]:
    """One docking attempt from a random free pose; its outcome and timings."""
    with Simulation(scenario) as sim:
        ctx = make_context(sim, config=config)
        cfg = config.charge
        grid = Navigator(sim.world, cfg.grid_resolution, cfg.robot_radius).grid()
        free = np.argwhere(~grid.blocked)
        cx, cy = grid.centre(tuple(free[rng.integers(len(free))]))
        half = grid.resolution / 2
        start = (cx + rng.uniform(-half, half), cy + rng.uniform(-half, half),
                 rng.uniform(-math.pi, math.pi))
        sim.robot.set_pose(*start)
        tree = SimulationTree(approach(ctx), sim, ctx)
        tree.setup()
        wall = time.perf_counter()
        while tree.root.status in (Status.INVALID, Status.RUNNING):
            tree.tick()
        wall = time.perf_counter() - wall
        x, y, yaw = sim.robot.pose()
        dock = sim.world.dock_pose()
        docked = ctx.events.of_kind("docked")
        return {"start": [round(v, 3) for v in start],
                "success": tree.root.status == Status.SUCCESS,
                "time_s": docked[0]["t"] if docked else None,
                "position_error": round(math.hypot(x - dock.x, y - dock.y), 4),
                "yaw_error_deg": round(abs(math.degrees(wrap_angle(yaw - dock.yaw))), 3),
                "replans": len(ctx.events.of_kind("replan")), "wall_s": round(wall, 3)}


def summary(name: str, trials: list[dict[str, Any]]) -> dict[str, Any]:
    """Success rate and the distributions of time to dock and final errors."""
    ok = [t for t in trials if t["success"]]
    times = [t["time_s"] for t in ok] or [math.nan]
    pos = [t["position_error"] for t in ok] or [math.nan]
    yaw = [t["yaw_error_deg"] for t in ok] or [math.nan]
    return {"world": name, "trials": len(trials), "success": round(len(ok) / len(trials), 4),
            "time_median_s": round(float(np.median(times)), 2),
            "time_p95_s": round(float(np.percentile(times, 95)), 2),
            "position_error_median_m": round(float(np.median(pos)), 4),
            "position_error_max_m": round(float(np.max(pos)), 4),
            "yaw_error_median_deg": round(float(np.median(yaw)), 3),
            "yaw_error_max_deg": round(float(np.max(yaw)), 3),
            "replans_mean": round(float(np.mean([t["replans"] for t in trials])), 2),
            "wall_s_per_trial": round(float(np.mean([t["wall_s"] for t in trials])), 3)}


COLUMNS = (("world", "{:<18}"), ("trials", "{:>6}"), ("success", "{:>8.1%}"),
           ("time_median_s", "{:>9.1f}"), ("time_p95_s", "{:>8.1f}"),
           ("position_error_median_m", "{:>9.3f}"), ("position_error_max_m", "{:>9.3f}"),
           ("yaw_error_median_deg", "{:>9.2f}"), ("yaw_error_max_deg", "{:>9.2f}"),
           ("replans_mean", "{:>8.2f}"), ("wall_s_per_trial", "{:>8.2f}"))
HEADER = ("world", "trials", "success", "t med s", "t p95 s", "pos med", "pos max", "yaw med",
          "yaw max", "replans", "wall s")


def table(rows: list[dict[str, Any]]) -> str:
    """The summaries as a fixed-width text table."""
    widths = [len(fmt.format(rows[0][key])) for key, fmt in COLUMNS]
    lines = [" ".join(h.rjust(w) if i else h.ljust(w)
                      for i, (h, w) in enumerate(zip(HEADER, widths, strict=True)))]
    lines += [" ".join(fmt.format(row[key]) for key, fmt in COLUMNS) for row in rows]
    return "\n".join(lines)


def main() -> None:
    """Run the trials, print the table and optionally write everything as JSON."""
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--trials", type=int, default=100, help="trials per world")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--world", nargs="*", default=None,
                        help="world names in worlds/ (default: all)")
    parser.add_argument("--json", type=Path, default=None, help="write summaries and trials")
    args = parser.parse_args()
    names = args.world or sorted(p.stem for p in WORLDS.glob("*.yaml"))
    config = load_behaviour_config()
    rows, everything = [], {}
    for name in names:
        scenario = load_scenario(WORLDS / f"{name}.yaml")
        rng = np.random.default_rng([args.seed, zlib.crc32(name.encode())])
        trials = [trial(scenario, config, rng) for _ in range(args.trials)]
        rows.append(summary(name, trials))
        everything[name] = trials
    rows.append(summary("all", [t for ts in everything.values() for t in ts]))
    print(table(rows))
    if args.json is not None:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps({"seed": args.seed, "trials_per_world": args.trials,
                                         "summary": rows, "trials": everything}, indent=1))


if __name__ == "__main__":
    main()
