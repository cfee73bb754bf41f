"""The base's laser scanners, the obstacle memory and the charge skill's planner: people are
avoided once sensed, never looked up in the simulator."""

import math
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pybullet as p
import pytest

from app.wiring import make_context
from behaviours.config import load_behaviour_config
from behaviours.obstacle_sensing import ObstacleSensing
from robot.lasers import Scan
from robot.navigation import Navigator
from robot.obstacle_tracks import clusters
from robot.sensed_obstacles import ObstacleMemory
from sim.people import Part, build_body
from sim.robot import Robot
from sim.scenario import load_scenario
from sim.simulation import Simulation

WORLDS = Path(__file__).resolve().parents[1] / "worlds"
CFG = load_behaviour_config().charge
ROBOT = (4.0, 2.0, 0.0)            # low_battery_night's living room, facing the bedroom wall
IN_FRONT, BEHIND_WALL = (5.0, 2.0), (7.0, 2.0)   # the wall at x = 6 is 2 m ahead


@pytest.fixture
def client() -> Iterator[int]:
    cid = p.connect(p.DIRECT)
    yield cid
    p.disconnect(cid)


def test_a_ray_ends_on_a_box_at_its_distance_and_never_on_the_robot(client):
    robot = Robot(client, (0.0, 0.0, 0.0))
    lasers = robot.lasers
    n = lasers.cfg.rays
    empty = lasers.scan()
    assert not empty.hit.any()                       # nothing around, and not the robot itself
    reach = np.hypot(*(empty.ends - empty.origins).T)
    assert reach == pytest.approx(lasers.cfg.range_max_m - lasers.cfg.range_min_m)
    build_body(client, "box", [Part("box", (0.2, 0.6, 0.5), (1, 1, 1), (0, 0, 0.25))],
               (1.6, 0.0, 0.0))                        # its near face at x = 1.5
    build_body(client, "side", [Part("box", (0.6, 0.2, 0.5), (1, 1, 1), (0, 0, 0.25))],
               (0.0, 1.1, 0.0))                        # its near face at y = 1.0
    scan = lasers.scan()
    front, left = lasers.names.index("front"), lasers.names.index("left")
    middle = n // 2                                     # the ray along each scanner's facing
    assert scan.hit[front * n + middle] and scan.hit[left * n + middle]
    assert scan.ends[front * n + middle] == pytest.approx((1.5, 0.0), abs=1e-6)
    assert scan.ends[left * n + middle] == pytest.approx((0.0, 1.0), abs=1e-6)
    assert not scan.hit[lasers.names.index("right") * n:].any()   # nothing to the right


def test_the_memory_forgets_after_its_duration_or_when_a_ray_sees_through():
    memory = ObstacleMemory(np.zeros((40, 40), dtype=bool), (0.0, 0.0), 0.05, memory_s=2.0)
    memory.add(np.array([[1.0, 1.0]]), now=0.0)
    assert memory.active()[20, 20] and memory.active().sum() == 1
    memory.add(np.empty((0, 2)), now=1.9)
    assert memory.active()[20, 20]
    memory.add(np.empty((0, 2)), now=2.1)
    assert not memory.active().any()
    memory.add(np.array([[1.0, 1.0]]), now=3.0)
    memory.clear(Scan(  # a ray from (0.5, 1.0) to (1.8, 1.0)
        np.array([[0.5, 1.0]]), np.array([[1.8, 1.0]]), np.array([True])), 3.1)
    assert not memory.active().any()


def test_points_the_map_explains_are_not_obstacles():
    explained = np.zeros((40, 40), dtype=bool)
    explained[20, 20] = True
    memory = ObstacleMemory(explained, (0.0, 0.0), 0.05, memory_s=2.0)
    memory.add(np.array([[1.0, 1.0], [1.5, 1.5]]), now=0.0)
    assert not memory.active()[20, 20] and memory.active()[30, 30]


@pytest.fixture
def household() -> Iterator[tuple[Simulation, Navigator]]:
    """low_battery_night with Daniel in the house and the robot facing the bedroom wall."""
    sim = Simulation(load_scenario(WORLDS / "low_battery_night.yaml"))
    sim.world.advance(0.0, 241.0)                       # Daniel has come in
    sim.robot.base.set_pose(*ROBOT)
    nav = Navigator(sim.world.house, CFG.grid_resolution, CFG.robot_radius, CFG.obstacle_memory_s,
                    CFG.static_margin_m, CFG.sensed_clearance_m)
    yield sim, nav
    sim.close()


def place(sim: Simulation, where: tuple[float, float]) -> None:
    sim.world.people["Daniel"].place(*where, math.pi)


def test_a_person_behind_a_wall_is_not_among_the_planners_obstacles(household):
    sim, nav = household
    place(sim, BEHIND_WALL)
    assert nav.grid().is_free(*BEHIND_WALL)             # nothing is given ...
    nav.observe(sim.robot.lasers.scan(), 0.0)
    ctx = make_context(sim, config=load_behaviour_config())
    sensing = ObstacleSensing(ctx, nav)
    sensing.update(0.0, sim.robot.camera.frame_with_depth()[1], 0.0)
    assert nav.grid().is_free(*BEHIND_WALL)             # ... and the wall hides him
    assert not nav.memory.active().any()                # the wall is the map's own


def test_a_person_in_front_is_sensed_and_forgotten_once_out_of_sight(household):
    sim, nav = household
    place(sim, IN_FRONT)
    assert nav.grid().is_free(*IN_FRONT)                # not given: not an obstacle yet
    nav.observe(sim.robot.lasers.scan(), 0.0)
    assert not nav.grid().is_free(*IN_FRONT)            # his legs, seen by the front scanner
    assert nav.plan(ROBOT[:2], (5.8, 2.0)) != [ROBOT[:2], (5.8, 2.0)]   # the way goes round
    sim.robot.base.set_pose(ROBOT[0], ROBOT[1], math.pi)     # the robot turns its back on him
    nav.observe(sim.robot.lasers.scan(), CFG.obstacle_memory_s - 0.5)
    assert not nav.grid().is_free(*IN_FRONT)            # remembered ...
    nav.observe(sim.robot.lasers.scan(), CFG.obstacle_memory_s + 0.5)
    assert nav.grid().is_free(*IN_FRONT)                # ... for obstacle_memory_s


def test_the_depth_camera_adds_the_person_it_sees(household):
    sim, nav = household
    place(sim, IN_FRONT)
    sensing = ObstacleSensing(make_context(sim, config=load_behaviour_config()), nav)
    points = sensing.depth_points(sim.robot.camera.frame_with_depth()[1])
    near = np.hypot(points[:, 0] - IN_FRONT[0], points[:, 1] - IN_FRONT[1]) < 0.35
    assert near.sum() >= 10                             # his body, from legs to chest
    assert (points[:, 0] < 6.1).all()                   # nothing beyond the wall


@pytest.mark.parametrize(("offset", "share"), [((2.5, 0.0), 1.0), ((0.17, 0.63), None),
                                               ((0.6, 0.0), 0.0)])
def test_the_base_slows_near_a_person_ahead_and_stops_at_the_security_distance(
        household, offset, share):
    sim, nav = household
    place(sim, (ROBOT[0] + offset[0], ROBOT[1] + offset[1]))
    sensing = ObstacleSensing(make_context(sim, config=load_behaviour_config()), nav)
    sensing.update(0.0, None, -math.inf)
    (vx, vy, wz), held = sensing.guard(ROBOT, (0.5, 0.0, 0.3))
    assert (vy, wz) == (0.0, 0.3)                       # the base may always turn
    if share is None:                                  # to its left, within slow_distance_m
        assert 0.0 < vx < 0.5 and not held
    else:
        assert vx == pytest.approx(0.5 * share) and held == (share == 0.0)
    (vx, _, _), held = sensing.guard(ROBOT, (-0.5, 0.0, 0.0))
    assert vx == -0.5 and not held                      # backing away from him: full speed


def test_hits_close_together_are_one_object_and_people_apart_are_two():
    legs = np.array([[1.0, 1.0], [1.0, 1.05], [1.0, 1.25], [1.0, 1.3]])   # two legs, 0.2 apart
    other = np.array([[2.0, 1.0], [2.0, 1.05]])
    centres = clusters(np.vstack([legs, other]), 0.3)
    assert sorted(map(tuple, centres.round(3))) == [(1.0, 1.15), (2.0, 1.025)]


def rays(starts: list[tuple[float, float]], ends: list[tuple[float, float]],
         hit: bool) -> Scan:
    """A scan of rays from ``starts`` to ``ends``, all ending on a surface or none."""
    return Scan(np.array(starts, dtype=float), np.array(ends, dtype=float),
                np.full(len(starts), hit))


def test_a_track_out_of_sight_is_expected_where_its_walk_takes_it_until_seen_free():
    memory = ObstacleMemory(np.zeros((60, 60), dtype=bool), (0.0, 0.0), 0.05, memory_s=2.0,
                            tracks=CFG.tracks)
    for k in range(5):                                  # walking along x at 1 m/s, seen
        at = (1.02 + 0.1 * k, 1.02)
        memory.observe(rays([(at[0], 0.2)], [at], hit=True), 0.1 * k)
    assert not memory.expected.any()                    # seen: where its hits are
    memory.observe(rays([(0.2, 0.2)], [(0.2, 0.5)], hit=False), 0.6)   # gone out of sight
    i, j = np.nonzero(memory.expected)
    assert (i.mean() + 0.5) * 0.05 == pytest.approx(1.6, abs=0.05)    # at x = 1.6, y = 1.0
    assert (j.mean() + 0.5) * 0.05 == pytest.approx(1.0, abs=0.05)
    assert memory.active()[i, j].all()
    fan = [(1.2 + 0.05 * k, 0.0) for k in range(17)]    # rays passing x = 1.2-2.0, to y = 2.5
    memory.observe(rays(fan, [(x, 2.5) for x, _ in fan], hit=False), 0.7)
    assert not memory.expected.any() and memory.tracks.tracks == []   # seen free: forgotten


def test_someone_who_stood_still_is_kept_out_of_sight_longer_than_a_walker():
    """A walker's track lapses ``hold_s`` after the scans lost it; a track that stood still
    is kept ``still_hold_s``: a guest standing behind the robot is still there."""
    memory = ObstacleMemory(np.zeros((60, 60), dtype=bool), (0.0, 0.0), 0.05, memory_s=2.0,
                            tracks=CFG.tracks)
    for k in range(5):                                  # one standing, one walking along x
        memory.observe(rays([(1.0, 0.2), (0.5 + 0.1 * k, 2.3)], [(1.02, 1.02),
                            (0.52 + 0.1 * k, 2.02)], hit=True), 0.1 * k)
    elsewhere = rays([(0.2, 0.2)], [(0.2, 0.5)], hit=False)
    later = CFG.tracks.hold_s + 1.0
    assert CFG.tracks.still_hold_s > later
    memory.observe(elsewhere, later)
    (x, y), = [track.position for track in memory.tracks.tracks]
    assert (x, y) == pytest.approx((1.02, 1.02))        # the walker is forgotten
    assert memory.active()[20, 20]                     # the one standing is not
    memory.observe(elsewhere, 0.4 + CFG.tracks.still_hold_s + 0.1)
    assert memory.tracks.tracks == [] and not memory.active().any()


def test_a_person_walking_from_the_front_fan_into_the_gap_beside_it_is_still_avoided(household):
    sim, forgetful = household
    nav = Navigator(sim.world.house, CFG.grid_resolution, CFG.robot_radius, CFG.obstacle_memory_s,
                    CFG.static_margin_m, CFG.sensed_clearance_m, tracks=CFG.tracks)
    start, gap = np.array([4.8, 2.0]), np.array([4.45, 2.45])   # ahead; then 45 deg, 0.64 m
    for k in range(6):                                  # about 1 m/s, scanned at 10 Hz
        place(sim, tuple(start + (gap - start) * k / 5))
        for navigator in (nav, forgetful):
            navigator.observe(sim.robot.lasers.scan(), 0.1 * k)
    ctx = make_context(sim, config=load_behaviour_config())
    scan = sim.robot.lasers.scan()
    assert not scan.hit[np.hypot(*(scan.ends - gap).T) < 0.4].any()   # no ray finds him now
    ahead = (0.5, 0.0, 0.0)
    assert ObstacleSensing(ctx, forgetful).guard(ROBOT, ahead)[0] == ahead   # forgotten
    (vx, _, _), _ = ObstacleSensing(ctx, nav).guard(ROBOT, ahead)
    assert vx < 0.25                                    # tracked: the base slows beside him


@pytest.mark.parametrize("name", sorted(f.stem for f in WORLDS.glob("*.yaml")))
def test_every_scanner_hit_on_the_maps_walls_and_furniture_is_explained(name):
    """With no one about, nothing the scanners see is an obstacle off the map, from 150
    random free poses: ``static_margin_m`` is wide enough for the map's own surfaces."""
    scenario = load_scenario(WORLDS / f"{name}.yaml")
    with Simulation(scenario.model_copy(update={"people": ()})) as sim:
        nav = Navigator(sim.world.house, CFG.grid_resolution, CFG.robot_radius,
                        CFG.obstacle_memory_s, CFG.static_margin_m)
        free = np.argwhere(~nav.grid().blocked)
        rng = np.random.default_rng(0)
        for _ in range(150):
            x, y = nav.grid().centre(tuple(free[rng.integers(len(free))]))
            sim.robot.base.set_pose(x, y, rng.uniform(-math.pi, math.pi))
            nav.observe(sim.robot.lasers.scan(), 0.0)
        assert not nav.memory.active().any()
