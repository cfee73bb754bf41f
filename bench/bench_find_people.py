"""Find-people skill benchmark: the robot must find, approach and greet one standing person.

Each trial is worlds/living_room.yaml with only Tom (1.8 m, standing) left in it, at a random
free spot anywhere in the room (behind the robot too) and turned within +-60 degrees of
facing the robot; the robot starts at a random free pose. The skill sees only the YOLO
detector's boxes. A trial succeeds when the skill confirms the person (``person_found``)
within 30 simulated seconds; after the greeting has been said the benchmark measures, from
the simulator's ground truth, the bearing error (robot heading vs. direction to the person)
and the distance error (|base-to-person distance - 1.0 m|). The summary also counts the
trials that succeeded with both errors within their bars (the strict reading of the bar).

``--close`` places Tom instead 0.4-0.8 m in front of the robot, within +-20 degrees of its
heading and facing it within +-30 degrees: a person who stepped up to the robot, their head
above the frame, whom the robot must back off from before it can see their face.

``--pose sitting`` seats Tom instead (a resident in a nursing home): his head is then at
about the camera's height, so the box height no longer tells the distance; the depth image
does.

``--facing DEG`` turns Tom within +-DEG (default 60) of facing the robot's start instead:
90 makes many trials side-on, like residents who face a table or the television; 180 turns
him any way at all. The skill uses the facing model (``assets/models/facing.pt``) to go
round to the front of someone turned away; ``--no-facing`` runs it without. The summary
also counts the successes greeted within 45 degrees of where Tom looks.

Usage: python bench/bench_find_people.py [--trials 100] [--seed 0] [--close]
                                         [--pose standing|sitting] [--facing DEG]
                                         [--weights PATH] [--no-facing] [--json PATH]
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

import numpy as np
import pybullet as p
from py_trees.common import Status

from app.harness import skill_tree
from app.wiring import make_context
from behaviours.config import load_behaviour_config
from behaviours.skills import find_people
from perception.detector.yolo import Detector, YoloDetector
from perception.facing.config import DEFAULT_FACING_MODEL
from perception.facing.model import FacingEstimator
from robot.geometry import Footprint
from robot.speaker import speech_seconds
from sim.layout import Placement
from sim.scenario import Scenario, Start, load_scenario
from sim.simulation import Simulation
from sim.world import World

ROOT = Path(__file__).resolve().parents[1]
SCENARIO = ROOT / "worlds" / "living_room.yaml"
WEIGHTS = (ROOT / "assets" / "models" / "detector.onnx",
           ROOT / "assets" / "models" / "detector.pt",
           ROOT / "runs" / "train-detector" / "weights" / "best.pt")
PERSON = "Tom"               # the living room's standing person
TARGET_DISTANCE_M = 1.0      # base to body centre where the skill stops (docs/find_people.md)
BUDGET_S = 30.0              # simulated seconds to confirm the person
FACING_DEG = 60.0            # the person faces the robot within this
MIN_SEPARATION_M = 1.2       # robot and person start at least this far apart
GAZE_DEG = 45.0              # greeted "in their view": the robot this close to where they look
PERSON_CLEARANCE_M = 0.3     # free spot: this far from walls and obstacles
ROBOT_CLEARANCE_M = 0.35     # the robot's radius (0.23 m) plus room to turn
CLOSE_M = (0.4, 0.8)         # --close: the person stands this far in front of the robot
CLOSE_CLEARANCE_M = 0.6      # --close: the robot's spot leaves room to back off
BARS = {"success_pct": 95.0, "bearing_error_deg": 5.0, "distance_error_m": 0.15}


def default_weights() -> Path:
    """The shipped detector if present, else the training run's best weights."""
    return next((w for w in WEIGHTS if w.is_file()), WEIGHTS[0])


def obstacles(scenario: Scenario) -> list[Footprint]:
    """Floor footprints of the scenario's walls, furniture, objects and dock."""
    client = p.connect(p.DIRECT)
    try:
        return World(scenario, client).obstacles()
    finally:
        p.disconnect(client)


def free_spot(scenario: Scenario, blocked: list[Footprint], rng: np.random.Generator,
              clearance: float) -> tuple[float, float]:
    """A uniformly drawn floor point at least ``clearance`` from walls and obstacles."""
    room = scenario.rooms[0]
    while True:
        x, y = rng.uniform(*room.x), rng.uniform(*room.y)
        if scenario.in_rooms(x, y, clearance) and not any(
                f.contains(x, y, clearance) for f in blocked):
            return float(x), float(y)


def placement(scenario: Scenario, blocked: list[Footprint], rng: np.random.Generator,
              facing_deg: float = FACING_DEG) -> tuple[Placement, Start]:
    """A random free robot pose and a person spot at least MIN_SEPARATION_M away, the
    person facing the robot within +-``facing_deg``."""
    rx, ry = free_spot(scenario, blocked, rng, ROBOT_CLEARANCE_M)
    while True:
        px, py = free_spot(scenario, blocked, rng, PERSON_CLEARANCE_M)
        if math.hypot(px - rx, py - ry) >= MIN_SEPARATION_M:
            break
    facing = math.degrees(math.atan2(ry - py, rx - px)) + rng.uniform(-facing_deg, facing_deg)
    return (Placement(x=rx, y=ry, yaw=float(rng.uniform(-180.0, 180.0))),
            Start(x=px, y=py, yaw=float(facing), pose="standing"))


def close_placement(scenario: Scenario, blocked: list[Footprint], rng: np.random.Generator
                    ) -> tuple[Placement, Start]:
    """A free robot spot with the person CLOSE_M in front of it (within +-20 degrees of its
    heading), facing the robot within +-30 degrees."""
    while True:
        rx, ry = free_spot(scenario, blocked, rng, CLOSE_CLEARANCE_M)
        heading = rng.uniform(-math.pi, math.pi)
        d = rng.uniform(*CLOSE_M)
        px, py = rx + d * math.cos(heading), ry + d * math.sin(heading)
        if scenario.in_rooms(px, py, PERSON_CLEARANCE_M) and not any(
                f.contains(px, py, PERSON_CLEARANCE_M) for f in blocked):
            break
    facing = math.degrees(heading + math.pi) + rng.uniform(-30.0, 30.0)
    robot_yaw = math.degrees(heading) + rng.uniform(-20.0, 20.0)
    return (Placement(x=rx, y=ry, yaw=float(robot_yaw)),
            Start(x=float(px), y=float(py), yaw=float(facing), pose="standing"))


def trial_scenario(base: Scenario, robot: Placement, person: Start) -> Scenario:
    """``base`` with only PERSON, standing still at ``person``, and the robot at ``robot``."""
    spec = next(q for q in base.people if q.name == PERSON)
    spec = spec.model_copy(update={"start": person, "events": ()})
    return base.model_copy(update={
        "people": (spec,), "robot": base.robot.model_copy(update={"start": robot})})


def run_trial(scenario: Scenario, detector: Detector, facing: FacingEstimator | None) -> dict:
    """Run the skill until the greeting has been said (or it fails, or time is up) and
    measure the errors against the person's true position and heading."""
    config = load_behaviour_config()
    limit = BUDGET_S + speech_seconds(config.find_people.greet) + 1.0
    with Simulation(scenario) as sim:
        ctx = make_context(sim, config, detector, facing=facing)
        skill = find_people.build(ctx)
        tree = skill_tree(sim, ctx, skill, "find_people")
        tree.setup()
        greeted = math.inf

        def greeting_over() -> bool:
            nonlocal greeted
            said = [e for e in ctx.events.of_kind("say") if e["behaviour"] == "Greet"]
            if said:
                greeted = said[0]["t"] + said[0]["duration"]
            return sim.t >= limit or sim.t >= greeted or skill.status == Status.FAILURE

        tree.run(until=greeting_over)
        found = ctx.events.of_kind("person_found")
        rx, ry, ryaw = sim.robot.base.pose()
        person = sim.world.people_positions()[PERSON]
        tree.stop()
    dist = math.hypot(person.x - rx, person.y - ry)
    bearing = math.remainder(math.atan2(person.y - ry, person.x - rx) - ryaw, math.tau)
    gaze = math.remainder(math.atan2(ry - person.y, rx - person.x) - person.yaw, math.tau)
    ok = bool(found) and found[0]["t"] <= BUDGET_S
    return {"success": ok, "found_s": found[0]["t"] if found else None,
            "bearing_error_deg": round(abs(math.degrees(bearing)), 3),
            "gaze_offset_deg": round(abs(math.degrees(gaze)), 1),
            "distance_m": round(dist, 3),
            "distance_error_m": round(abs(dist - TARGET_DISTANCE_M), 3),
            "no_face_events": len(ctx.events.of_kind("no_face"))}


def summarise(rows: list[dict]) -> dict:
    """Success rate and the error statistics of the successful trials."""
    good = [r for r in rows if r["success"]]
    out: dict = {"trials": len(rows), "success_pct": round(100.0 * len(good) / len(rows), 1)}
    within = [r for r in good if r["bearing_error_deg"] <= BARS["bearing_error_deg"]
              and r["distance_error_m"] <= BARS["distance_error_m"]]
    out["success_within_bounds_pct"] = round(100.0 * len(within) / len(rows), 1)
    seen = [r for r in good if r["gaze_offset_deg"] <= GAZE_DEG]
    out["success_in_their_view_pct"] = round(100.0 * len(seen) / len(rows), 1)
    for key in ("bearing_error_deg", "distance_error_m", "found_s"):
        v = np.array([r[key] for r in good], dtype=float)
        out[key] = ({"mean": round(float(v.mean()), 3), "median": round(float(np.median(v)), 3),
                     "p95": round(float(np.percentile(v, 95)), 3), "max": round(float(v.max()), 3)}
                    if len(v) else None)
    out["bars_met"] = {
        "success_pct": out["success_pct"] >= BARS["success_pct"],
        "success_within_bounds_pct": out["success_within_bounds_pct"] >= BARS["success_pct"],
        **{k: out[k] is not None and out[k]["mean"] <= BARS[k]
           for k in ("bearing_error_deg", "distance_error_m")}}
    return out


def table(summary: dict) -> str:
    """A markdown table of the summary against the bars."""
    lines = ["| measure | mean | median | p95 | max | bar (mean) | met |",
             "| --- | --- | --- | --- | --- | --- | --- |",
             f"| success | {summary['success_pct']} % | | | | >= {BARS['success_pct']} % | "
             f"{summary['bars_met']['success_pct']} |",
             f"| success with bearing and distance within the bars | "
             f"{summary['success_within_bounds_pct']} % | | | | >= {BARS['success_pct']} % | "
             f"{summary['bars_met']['success_within_bounds_pct']} |",
             f"| success, greeted within {GAZE_DEG:g} deg of where they look | "
             f"{summary['success_in_their_view_pct']} % | | | | | |"]
    for key, unit in (("bearing_error_deg", "deg"), ("distance_error_m", "m"), ("found_s", "s")):
        s = summary[key] or dict.fromkeys(("mean", "median", "p95", "max"), "-")
        bar = f"<= {BARS[key]} {unit}" if key in BARS else ""
        met = summary["bars_met"].get(key, "")
        lines.append(f"| {key} | {s['mean']} | {s['median']} | {s['p95']} | {s['max']} | "
                     f"{bar} | {met} |")
    return "\n".join(lines)


def main() -> None:
    """Run the trials; print a progress line per trial (stderr), the table and the JSON
    summary; ``--json`` also writes every trial to a file."""
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--trials", type=int, default=100)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--close", action="store_true",
                        help="the person stands 0.4-0.8 m in front of the robot")
    parser.add_argument("--pose", choices=("standing", "sitting"), default="standing")
    parser.add_argument("--facing", type=float, default=FACING_DEG,
                        help="the person faces the robot within +-this many degrees")
    parser.add_argument("--weights", type=Path, default=None,
                        help="YOLO weights (default: assets/models/detector.onnx, else .pt, else "
                             "runs/train-detector/weights/best.pt)")
    parser.add_argument("--no-facing", action="store_true",
                        help="run without the facing model (assets/models/facing.pt)")
    parser.add_argument("--json", type=Path, default=None, help="write every trial here")
    args = parser.parse_args()
    weights = args.weights or default_weights()
    detector = YoloDetector(weights)
    facing = (None if args.no_facing or not DEFAULT_FACING_MODEL.is_file()
              else FacingEstimator.load(DEFAULT_FACING_MODEL))
    base = load_scenario(SCENARIO)
    blocked = obstacles(base.model_copy(update={"people": ()}))
    rows, start = [], time.perf_counter()
    for i in range(args.trials):
        rng = np.random.default_rng([args.seed, i])
        robot, person = (close_placement(base, blocked, rng) if args.close
                         else placement(base, blocked, rng, args.facing))
        person = person.model_copy(update={"pose": args.pose})
        row = {"trial": i, "robot": robot.model_dump(), "person": person.model_dump(),
               **run_trial(trial_scenario(base, robot, person), detector, facing)}
        rows.append(row)
        print(json.dumps({k: row[k] for k in ("trial", "success", "found_s",
                                               "bearing_error_deg", "distance_m")}),
              file=sys.stderr, flush=True)
    summary = {"weights": str(weights), "seed": args.seed, "close": args.close,
               "pose": args.pose, "facing_deg": args.facing, "facing_model": facing is not None,
               **summarise(rows),
               "wall_s": round(time.perf_counter() - start, 1)}
    print(table(summary))
    print(json.dumps(summary))
    if args.json is not None:
        args.json.write_text(json.dumps({"summary": summary, "trials": rows}, indent=1) + "\n")


if __name__ == "__main__":
    main()
