"""Docking from anywhere: the charge skill's approach (path to the pre-dock pose, then straight
in) from random free poses in each household, until the ``docked`` event or the skill's
``timeout_s``.

Each trial builds the world afresh (people at their scenario starts, the timeline playing),
puts the robot in a free cell drawn uniformly from the occupancy grid (a uniform point in that
cell, uniform yaw) and ticks only the approach subtree. The planner knows the floor map and
senses everything else with the base's laser scanners; with ``--camera`` Sense runs before
it, so the head camera's depth frames add their points too.

``--crossers N`` adds N people to each trial who walk back and forth across the robot's
way: each crosses the path that the floor map alone gives (at a uniform 25-75 % of its
length, square to it, out to a drawn 1-2 m on either side as far as the floor is free,
at least 0.4 m, and 0.6 m clear of the last straight into the dock; at 0.6-1.2 m/s, from
a uniform phase). Like every person in the
simulation they go round the robot rather than into it, keeping the distance people keep
from each other (``World.advance``); with ``--blind-walkers`` nobody does. A
*contact* is the robot's own move bringing it within ``--contact-m`` of a person's body
(the simulator's closest points, for scoring only; the move closed at least ``DRIVEN_M``
on them in that step); ``touched`` counts any such closeness, also a person
walking into a robot that stands, creeps or turns on the spot.

Usage: python bench/bench_charge.py [--trials 100] [--seed 0] [--world NAME ...]
       [--crossers N] [--blind-walkers] [--camera] [--json PATH]
"""

from __future__ import annotations

import argparse
import itertools
import json
import math
import time
import zlib
from pathlib import Path
from typing import Any

import numpy as np
import pybullet as p
from py_trees.common import Status

from app.harness import skill_tree
from app.wiring import make_context
from behaviours.blackboard import seed
from behaviours.config import BehaviourConfig, load_behaviour_config
from behaviours.skills.charge import approach, predock_pose
from behaviours.ticking import SimulationTree
from robot.geometry import wrap_angle
from robot.navigation import Navigator, OccupancyGrid, Point
from sim.scenario import Event, PersonSpec, Scenario, Start, WalkTo, load_scenario
from sim.scenario_space import to_segment
from sim.simulation import Simulation
from sim.world import World

WORLDS = Path(__file__).resolve().parents[1] / "worlds"
PERSON_RADIUS_M = 0.25   # m kept from the map's obstacles by a walk across the robot's way
MIN_SIDE_M = 0.4   # m: a walk reaches at least this far to either side of the way
TRIES = 10
DRIVEN_M = 0.005   # m the robot's own move in one step must close on a person to be its doing
DOCK_CLEAR_M = 0.6   # m a walk keeps from the dock's last straight (robot radius and a person's)


def apart(a: tuple[Point, Point], b: tuple[Point, Point]) -> float:
    """The least distance (m) between the segments ``a`` and ``b`` (0 where they cross)."""
    def side(o: Point, p1: Point, p2: Point) -> float:
        return (p1[0] - o[0]) * (p2[1] - o[1]) - (p1[1] - o[1]) * (p2[0] - o[0])

    if side(*a, b[0]) * side(*a, b[1]) < 0 and side(*b, a[0]) * side(*b, a[1]) < 0:
        return 0.0
    return min(min(to_segment(*q, b) for q in a), min(to_segment(*q, a) for q in b))


def crossing(walkable: OccupancyGrid, path: list[Point], rng: np.random.Generator,
             dock_way: tuple[Point, Point]) -> tuple[Point, Point] | None:
    """The ends of a walk square to ``path`` across a uniform point of its middle half: on
    each side as far as a drawn 1-2 m while the way stays free for a person (``walkable``),
    at least ``MIN_SIDE_M``, and ``DOCK_CLEAR_M`` from ``dock_way`` (the last straight,
    pre-dock pose to dock: people cross the robot's way, they do not pace over its
    charger); up to ``TRIES`` draws, else None."""
    legs = [math.dist(a, b) for a, b in itertools.pairwise(path)]
    if sum(legs) < 0.5:
        return None
    for _ in range(TRIES):
        at = rng.uniform(0.25, 0.75) * sum(legs)
        k = 0
        while at > legs[k]:
            at, k = at - legs[k], k + 1
        (ax, ay), (bx, by) = path[k], path[k + 1]
        ux, uy = (bx - ax) / legs[k], (by - ay) / legs[k]
        centre, half = (ax + at * ux, ay + at * uy), rng.uniform(1.0, 2.0)
        if not walkable.is_free(*centre):
            continue
        ends = []
        for nx, ny in ((-uy, ux), (uy, -ux)):
            side = 0.0
            while side + 0.1 <= half and walkable.visible(
                    centre, (centre[0] + (side + 0.1) * nx, centre[1] + (side + 0.1) * ny)):
                side += 0.1
            ends.append((centre[0] + side * nx, centre[1] + side * ny))
        if (min(math.dist(centre, e) for e in ends) >= MIN_SIDE_M
                and apart((ends[0], ends[1]), dock_way) >= DOCK_CLEAR_M):
            return ends[0], ends[1]
    return None


def crosser(name: str, ends: tuple[Point, Point], horizon: float,
            rng: np.random.Generator) -> PersonSpec:
    """A person walking to and fro between ``ends`` until ``horizon`` s, at a uniform speed
    and a uniform point of the way when the trial starts."""
    speed = rng.uniform(0.6, 1.2)
    leg = math.dist(*ends) / speed
    k, done = int(rng.integers(2)), rng.uniform(0.0, 1.0)   # going to ends[k], share walked
    (ax, ay), (bx, by) = ends[1 - k], ends[k]
    start = Start(x=ax + done * (bx - ax), y=ay + done * (by - ay),
                  yaw=math.degrees(math.atan2(by - ay, bx - ax)))
    events, t = [], 0.0
    while t < horizon:
        events.append(Event(at=t, walk_to=WalkTo(x=ends[k][0], y=ends[k][1], speed=speed)))
        t, k = t + (leg * (1.0 - done) if len(events) == 1 else leg), 1 - k
    return PersonSpec(name=name, start=start, events=tuple(events))


def closeness(sim: Simulation, before: tuple[float, float, float], limit: float,
              ) -> tuple[bool, bool]:
    """Whether the robot is within ``limit`` of a person's body now (the simulator's truth),
    and whether its own move since ``before`` brought it there: from ``before`` it was more
    than ``DRIVEN_M`` farther from that person as they stand now."""
    robot, now = sim.robot, sim.robot.base.pose()
    near = [person.body_id for person in sim.world.people.values()
            if math.hypot(person.x - now[0], person.y - now[1]) < 1.5]

    def gaps() -> list[float]:
        return [min((c[8] for c in p.getClosestPoints(robot.body_id, body, limit,
                                                      physicsClientId=sim.client)),
                    default=math.inf) for body in near]

    gap_now = gaps()
    if not any(g < limit for g in gap_now):
        return False, False
    robot.base.set_pose(*before)
    gap_before = gaps()
    robot.base.set_pose(*now)
    return True, any(g < limit and g < b - DRIVEN_M
                     for g, b in zip(gap_now, gap_before, strict=True))


def trial(scenario: Scenario, config: BehaviourConfig, rng: np.random.Generator,
          crossers: int = 0, camera: bool = False, contact_m: float = 0.05,
          blind: bool = False) -> dict[str, Any]:
    """One docking attempt from a random free pose; its outcome, timings and contacts
    (with ``blind``, no one gives way to the robot)."""
    cfg = config.charge
    client = p.connect(p.DIRECT)
    try:   # the floor map, and the way it alone gives to the pre-dock pose
        world = World(scenario, client)
        navigator = Navigator(world.house, cfg.grid_resolution, cfg.robot_radius)
        grid, dock = navigator.grid(), world.house.dock_pose()
        walkable = OccupancyGrid.build(world.house.room_bounds().values(), world.obstacles(),
                                       cfg.grid_resolution, PERSON_RADIUS_M)
        # the trial's set-up, not the robot's knowledge: no start inside a person
        people = [o for o in world.obstacles(include_people=True) if o.kind == "person"]
        free = np.argwhere(~grid.with_obstacles(people).blocked)
        cx, cy = grid.centre(tuple(free[rng.integers(len(free))]))
        half = grid.resolution / 2
        start = (cx + rng.uniform(-half, half), cy + rng.uniform(-half, half),
                 rng.uniform(-math.pi, math.pi))
        pre = predock_pose(dock, cfg.predock_distance)
        path = (navigator.plan(start[:2], (pre.x, pre.y)) or []) if crossers else []
    finally:
        p.disconnect(client)
    dock_way = ((pre.x, pre.y), (dock.x, dock.y))
    people = [crosser(f"Crosser{i}", ends, cfg.timeout_s + 5.0, rng) for i in range(crossers)
              if len(path) > 1 and (ends := crossing(walkable, path, rng, dock_way)) is not None]
    everyone = (*scenario.people, *people)
    if blind:
        everyone = tuple(q.model_copy(update={"gives_way": False}) for q in everyone)
    scenario = scenario.model_copy(update={"people": everyone})
    with Simulation(scenario) as sim:
        ctx = make_context(sim, config=config)
        sim.robot.base.set_pose(*start)
        if camera:
            tree = skill_tree(sim, ctx, approach(ctx), "charge")
            skill = tree.root.children[-1]
        else:
            seed(ctx, scenario.robot.initial_drives(), action="charge")
            tree = SimulationTree(approach(ctx), sim, ctx)
            skill = tree.root
        tree.setup()
        wall = time.perf_counter()
        contacts = touched = 0
        before = sim.robot.base.pose()

        def score() -> None:
            nonlocal before, contacts, touched
            close, driven = closeness(sim, before, contact_m)
            touched += close
            contacts += driven
            before = sim.robot.base.pose()

        tree.run(until=lambda: skill.status not in (Status.INVALID, Status.RUNNING),
                 after_tick=score)
        wall = time.perf_counter() - wall
        x, y, yaw = sim.robot.base.pose()
        docked = ctx.events.of_kind("docked")
        replans = ctx.events.of_kind("replan")
        return {"start": [round(v, 3) for v in start],
                "success": skill.status == Status.SUCCESS,
                "time_s": docked[0]["t"] if docked else None,
                "position_error": round(math.hypot(x - dock.x, y - dock.y), 4),
                "yaw_error_deg": round(abs(math.degrees(wrap_angle(yaw - dock.yaw))), 3),
                "replans": len(replans), "crossers": len(people),
                "contact_ticks": int(contacts), "touched_ticks": touched,
                "wall_s": round(wall, 3)}


def summary(name: str, trials: list[dict[str, Any]]) -> dict[str, Any]:
    """Success rate, the distributions of time to dock and final errors, and the trials
    with a contact (and with any closeness) between the robot and a person."""
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
            "contacts": sum(t["contact_ticks"] > 0 for t in trials),
            "touched": sum(t["touched_ticks"] > 0 for t in trials),
            "wall_s_per_trial": round(float(np.mean([t["wall_s"] for t in trials])), 3)}


COLUMNS = (("world", "{:<18}"), ("trials", "{:>6}"), ("success", "{:>8.1%}"),
           ("time_median_s", "{:>9.1f}"), ("time_p95_s", "{:>8.1f}"),
           ("position_error_median_m", "{:>9.3f}"), ("position_error_max_m", "{:>9.3f}"),
           ("yaw_error_median_deg", "{:>9.2f}"), ("yaw_error_max_deg", "{:>9.2f}"),
           ("replans_mean", "{:>8.2f}"), ("contacts", "{:>8}"), ("touched", "{:>8}"),
           ("wall_s_per_trial", "{:>8.2f}"))
HEADER = ("world", "trials", "success", "t med s", "t p95 s", "pos med", "pos max", "yaw med",
          "yaw max", "replans", "contacts", "touched", "wall s")


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
    parser.add_argument("--crossers", type=int, default=0,
                        help="people per trial walking to and fro across the robot's way")
    parser.add_argument("--blind-walkers", action="store_true",
                        help="people walk into the robot rather than round it")
    parser.add_argument("--camera", action="store_true",
                        help="run Sense before the approach: depth frames add obstacle points")
    parser.add_argument("--contact-m", type=float, default=0.05,
                        help="robot-person distance (m) counted as a contact")
    parser.add_argument("--json", type=Path, default=None, help="write summaries and trials")
    args = parser.parse_args()
    names = args.world or sorted(f.stem for f in WORLDS.glob("*.yaml"))
    config = load_behaviour_config()
    rows, everything = [], {}
    for name in names:
        scenario = load_scenario(WORLDS / f"{name}.yaml")
        rng = np.random.default_rng([args.seed, zlib.crc32(name.encode())])
        trials = [trial(scenario, config, rng, args.crossers, args.camera, args.contact_m,
                        args.blind_walkers) for _ in range(args.trials)]
        rows.append(summary(name, trials))
        everything[name] = trials
    rows.append(summary("all", [t for ts in everything.values() for t in ts]))
    print(table(rows))
    if args.json is not None:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps({"seed": args.seed, "trials_per_world": args.trials,
                                         "crossers": args.crossers, "camera": args.camera,
                                         "blind_walkers": args.blind_walkers,
                                         "summary": rows, "trials": everything}, indent=1))


if __name__ == "__main__":
    main()
