"""The base's laser scanners, the obstacle memory and the charge skill's planner: people are
avoided once sensed, never looked up in the simulator."""

import math
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pybullet as p
import pytest

from app.sim.lasers import Scan
from app.sim.navigation import Navigator
from app.sim.people import Part, build_body
from app.sim.robot import Robot
from app.sim.scenario import load_scenario
from app.sim.sensed_obstacles import ObstacleMemory
from app.sim.simulation import Simulation
from behaviours.config import load_behaviour_config
from behaviours.context import make_context
from behaviours.obstacle_sensing import ObstacleSensing

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
    sim.robot.set_pose(*ROBOT)
    nav = Navigator(sim.world, CFG.grid_resolution, CFG.robot_radius, CFG.obstacle_memory_s,
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
    sensing.update(0.0, sim.robot.camera_frame_with_depth()[1], 0.0)
    assert nav.grid().is_free(*BEHIND_WALL)             # ... and the wall hides him
    assert not nav.memory.active().any()                # the wall is the map's own


def test_a_person_in_front_is_sensed_and_forgotten_once_out_of_sight(household):
    sim, nav = household
    place(sim, IN_FRONT)
    assert nav.grid().is_free(*IN_FRONT)                # not given: not an obstacle yet
    nav.observe(sim.robot.lasers.scan(), 0.0)
    assert not nav.grid().is_free(*IN_FRONT)            # his legs, seen by the front scanner
    assert nav.plan(ROBOT[:2], (5.8, 2.0)) != [ROBOT[:2], (5.8, 2.0)]   # the way goes round
    sim.robot.set_pose(ROBOT[0], ROBOT[1], math.pi)     # the robot turns its back on him
    nav.observe(sim.robot.lasers.scan(), CFG.obstacle_memory_s - 0.5)
    assert not nav.grid().is_free(*IN_FRONT)            # remembered ...
    nav.observe(sim.robot.lasers.scan(), CFG.obstacle_memory_s + 0.5)
    assert nav.grid().is_free(*IN_FRONT)                # ... for obstacle_memory_s


def test_the_depth_camera_adds_the_person_it_sees(household):
    sim, nav = household
    place(sim, IN_FRONT)
    sensing = ObstacleSensing(make_context(sim, config=load_behaviour_config()), nav)
    points = sensing.depth_points(sim.robot.camera_frame_with_depth()[1])
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
