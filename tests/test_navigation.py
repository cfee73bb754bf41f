"""Occupancy grid, A* paths, the PID path follower and the charge skill (docking)."""

import math
from collections.abc import Iterator
from itertools import pairwise
from pathlib import Path

import numpy as np
import pybullet as p
import pytest
from py_trees.common import Status

from app.harness import run_skill
from app.wiring import make_context
from behaviours.config import load_behaviour_config
from behaviours.skills.charge import approach, build, predock_pose
from core.config_files import ConfigError
from mind.personality import ACTIONS
from robot.geometry import Footprint, Pose2D
from robot.navigation import (
    Navigator,
    OccupancyGrid,
    Planner,
    footprint_distance,
)
from robot.path_follower import PathFollower
from sim.scenario import load_scenario
from sim.simulation import Simulation
from sim.world import World

WORLDS = Path(__file__).resolve().parents[1] / "worlds"
CFG = load_behaviour_config()
RES, RADIUS = CFG.charge.grid_resolution, CFG.charge.robot_radius


@pytest.fixture
def client() -> Iterator[int]:
    cid = p.connect(p.DIRECT)
    yield cid
    p.disconnect(cid)


def world(name: str, client: int) -> World:
    return World(load_scenario(WORLDS / f"{name}.yaml"), client)


def test_grid_inflates_a_box_by_the_radius_and_blocks_the_outside():
    box = Footprint("box", "furniture", 2.0, 1.5, 0.0, 0.3, 0.2)
    grid = OccupancyGrid.build([(0.0, 0.0, 4.0, 3.0)], [box], RES, RADIUS)
    assert not grid.is_free(2.0, 1.5)
    assert not grid.is_free(2.3 + RADIUS - 0.03, 1.5)        # within the radius of its side
    assert grid.is_free(2.3 + RADIUS + 0.03, 1.5)
    assert grid.is_free(2.575, 1.975)           # a cell centre 0.39 m off the corner, diagonally
    assert not grid.is_free(0.2, 1.5) and not grid.is_free(3.8, 2.9)   # near the outside
    assert not grid.is_free(-0.5, 1.5)                         # outside (clamped to the edge)


def test_living_room_grid_blocks_furniture_walls_and_door_to_outside(client):
    grid = Navigator(world("living_room", client).house, RES, RADIUS).grid()
    for x, y in [(3.0, 4.45), (3.0, 3.3), (1.0, 3.0), (5.78, 2.5), (4.6, 1.6),  # sofa ... ball
                 (0.0, 2.5), (6.0, 1.0), (3.0, 5.0), (1.0, 0.1)]:           # walls, hall door
        assert not grid.is_free(x, y), (x, y)
    assert grid.is_free(4.3, 2.6) and grid.is_free(2.0, 1.5)


@pytest.mark.parametrize("name", ["living_room", "low_battery_night", "nursing_home"])
def test_planned_paths_keep_clear_of_every_obstacle(name, client):
    w = world(name, client)
    nav = Navigator(w.house, RES, RADIUS)
    grid = nav.grid()
    free = np.argwhere(~grid.blocked)
    rng = np.random.default_rng(3)
    half_diagonal = RES / math.sqrt(2)
    for _ in range(4):
        start, goal = (grid.centre(tuple(free[k])) for k in rng.integers(len(free), size=2))
        path = nav.plan(start, goal)
        assert path is not None and path[0] == start and path[-1] == goal
        for a, b in pairwise(path):
            assert grid.visible(a, b)               # every cell the segment passes is free ...
            t = np.linspace(0, 1, max(2, int(math.dist(a, b) / 0.01)))
            xs, ys = a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])
            clearance = min(footprint_distance(f, xs, ys).min() for f in w.obstacles())
            assert clearance > RADIUS - half_diagonal   # ... so it keeps the radius, to a cell


def test_start_inside_an_inflated_obstacle_snaps_to_a_free_cell():
    box = Footprint("box", "furniture", 2.0, 1.5, 0.0, 0.3, 0.2)
    planner = Planner(OccupancyGrid.build([(0.0, 0.0, 4.0, 3.0)], [box], RES, RADIUS))
    path = planner.plan((2.0, 1.85), (2.0, 0.6))                # starts against the box
    assert path is not None and planner.grid.is_free(*path[0])
    assert math.dist(path[0], (2.0, 1.85)) < 0.2 and path[-1] == (2.0, 0.6)
    assert all(planner.grid.visible(a, b) for a, b in pairwise(path))


def test_a_robot_in_a_pocket_behind_furniture_slides_out_where_its_base_fits(client):
    w = world("dislikes_dancing", client)    # behind the armchair, its corner 0.6 m from the wall
    nav = Navigator(w.house, RES, RADIUS, body=CFG.charge.body_radius)
    body = nav.planner.body
    start, goal = (0.43, 0.37), (4.6, 1.0)
    path = nav.plan(start, goal)
    assert path is not None and path[-1] == goal
    slide = [start, *path[:next(k for k, q in enumerate(path) if nav.grid().is_free(*q)) + 1]]
    assert len(slide) > 2                                 # not one straight slide: round the corner
    assert all(body.visible(a, b) for a, b in pairwise(slide[1:]))
    assert not body.clear_ahead(start, slide[-1])         # the straight slide would hit the chair
    assert Navigator(w.house, RES, RADIUS).plan(start, goal)[0] == slide[-1]   # which it was


def test_clear_ahead_skips_the_blocked_cells_around_the_start_only():
    box = Footprint("box", "furniture", 2.0, 1.5, 0.0, 0.3, 0.2)
    grid = OccupancyGrid.build([(0.0, 0.0, 4.0, 3.0)], [box], RES, RADIUS)
    assert not grid.is_free(2.0, 1.85)                   # against the box's north side
    assert grid.clear_ahead((2.0, 1.85), (2.0, 2.5))     # leaving it: clear
    assert not grid.visible((2.0, 1.85), (2.0, 2.5))
    assert not grid.clear_ahead((2.0, 2.5), (2.0, 0.5))  # across the box: not clear
    assert not grid.clear_ahead((2.0, 1.85), (2.0, 0.5))


def test_nearest_goal_goes_by_path_length_not_straight_line():
    wall = Footprint("wall", "furniture", 2.0, 1.2, 0.0, 0.05, 1.2)   # x = 2, from y 0 to 2.4
    planner = Planner(OccupancyGrid.build([(0.0, 0.0, 4.0, 3.0)], [wall], RES, RADIUS))
    behind, around = (2.6, 0.6), (1.2, 2.7)      # 1.3 m away through the wall; 2.2 m in the open
    assert planner.nearest_goal((1.4, 0.6), [behind, around]) == around
    assert planner.nearest_goal((1.4, 0.6), [(2.0, 1.0)]) is None          # inside the wall


def test_path_follower_turns_on_the_spot_then_reaches_the_goal():
    t = [0.0]
    follower = PathFollower(CFG.pid, 0.55, 2.0, 0.15, lambda: t[0])
    follower.start([(0.0, 0.0), (2.0, 0.0), (2.0, 1.5)])
    x, y, yaw = 0.0, 0.0, math.pi                               # facing away from the path
    vx, _, wz = follower.command((x, y, yaw))
    assert vx == 0.0 and abs(wz) > 0.0
    for _ in range(300):
        t[0] += 0.1
        vx, _, wz = follower.command((x, y, yaw))
        yaw += wz * 0.1
        x, y = x + vx * math.cos(yaw) * 0.1, y + vx * math.sin(yaw) * 0.1
    assert follower.arrived(x, y) and follower.command((x, y, yaw)) == (0.0, 0.0, 0.0)


def charge_run(name: str, max_seconds: float, charge_steps: int | None = 3,
               config=CFG, start=None):
    """Run the charge subtree with run_skill; (status, context, simulation)."""
    sim = Simulation(load_scenario(WORLDS / f"{name}.yaml"))
    if start is not None:
        sim.robot.base.set_pose(*start)
    ctx = make_context(sim, config=config)
    if charge_steps is not None:
        ctx.homeostasis.duration[ACTIONS.index("charge")] = charge_steps
    status, _ = run_skill(sim, ctx, build(ctx), "charge", max_seconds)
    return status, ctx, sim


@pytest.mark.parametrize("name, start", [
    ("living_room", (1.2, 1.2, 0.5)),
    ("living_room", (2.27, 0.80, 0.12)),    # against the TV's corner, inside its inflation
    ("low_battery_night", None)])           # from the scenario's start; dock in the bedroom
def test_charge_docks_charges_and_unplugs(name, start):
    status, ctx, sim = charge_run(name, 120.0, start=start)
    try:
        assert status == Status.SUCCESS
        kinds = [e["kind"] for e in ctx.events.events
                 if e["kind"] in ("say", "docked", "charging", "unplugged")]
        assert kinds == ["say", "docked", "charging", "unplugged", "say"]
        says = ctx.events.of_kind("say")
        assert [s["text"] for s in says] == [CFG.charge.ask, CFG.charge.done]
        docked = ctx.events.of_kind("docked")[0]
        assert docked["position_error"] <= CFG.charge.dock_position_tolerance
        assert docked["yaw_error_deg"] <= CFG.charge.dock_yaw_tolerance_deg
        assert not ctx.events.of_kind("unplugged")[0]["interrupted"]
        assert not sim.robot.battery.charging and sim.robot.base.velocity == (0.0, 0.0, 0.0)
        dock = sim.world.house.dock_pose()
        assert math.dist(sim.robot.base.pose()[:2], dock[:2]) <= CFG.charge.dock_position_tolerance
    finally:
        sim.close()


def test_interrupted_while_charging_unplugs():
    status, ctx, sim = charge_run("living_room", 40.0, charge_steps=None)   # 1000 steps
    try:
        assert status == Status.RUNNING        # still charging when run_skill stops the tree
        assert ctx.events.of_kind("docked") and ctx.events.of_kind("charging")
        assert ctx.events.of_kind("unplugged")[0]["interrupted"]
        assert not sim.robot.battery.charging
    finally:
        sim.close()


def test_gives_up_after_the_timeout_and_stops():
    config = CFG.model_copy(update={"charge": CFG.charge.model_copy(update={"timeout_s": 3.0})})
    status, ctx, sim = charge_run("low_battery_night", 30.0, config=config)
    try:
        assert status == Status.FAILURE and ctx.events.of_kind("dock_failed")
        assert not ctx.events.of_kind("docked")
        assert sim.robot.base.velocity == (0.0, 0.0, 0.0) and not sim.robot.battery.charging
    finally:
        sim.close()


@pytest.mark.parametrize(("text", "expected"), [
    ("charge:\n  slow_distance_m: 0.2\n", "need slow_distance_m > security_distance_m"),
    ("charge:\n  body_radius: 0.4\n", "need body_radius <= robot_radius"),
    ("charge:\n  tracks: {smoothing: 0.0}\n", "tracks.smoothing"),
    ("charge:\n  tracks: {gate_m: -0.5}\n", "tracks.gate_m"),
    ("charge:\n  tracks: {speed: 2.0}\n", "tracks.speed"),
    ("charge:\n  tracks: {still_hold_s: -1}\n", "tracks.still_hold_s"),
])
def test_bad_charge_settings_are_refused_by_name(tmp_path, text, expected):
    path = tmp_path / "behaviour.yaml"
    path.write_text(text)
    with pytest.raises(ConfigError, match=expected):
        load_behaviour_config(path)


def test_the_last_straight_knows_what_the_scanners_sensed_on_the_way():
    with Simulation(load_scenario(WORLDS / "low_battery_night.yaml")) as sim:
        sim.world.advance(0.0, 241.0)                   # Daniel has come in ...
        sim.robot.base.set_pose(4.0, 2.0, 0.0)
        sim.world.people["Daniel"].place(5.0, 2.0, math.pi)   # ... and stands 1 m ahead
        tree = approach(make_context(sim, config=CFG))
        tree.setup_with_descendants()
        follow, dock_in = tree.decorated.children
        follow.sensing.update(0.0, None, -math.inf)    # the path's scanners see him
        assert dock_in.sensing.navigator.memory.active().any()


def test_predock_pose_lies_behind_the_dock():
    pre = predock_pose(Pose2D(5.3, 0.6, -math.pi / 2), 0.5)     # living room: facing -y
    assert (pre.x, pre.y, pre.yaw) == pytest.approx((5.3, 1.1, -math.pi / 2))
