"""The simulated robot: URDF, postures, joint and base motion, camera, battery, heat."""

import math

import numpy as np
import pybullet as p
import pytest

from robot.joints import JOINT_NAMES
from robot.percepts import FeedbackEvent, HeardLine
from sim.head_camera import decode_segmentation
from sim.power import MotorHeat
from sim.robot import URDF_PATH, Robot
from sim.robot_config import load_robot_config

DT = 1.0 / 240.0
CFG = load_robot_config()


@pytest.fixture
def world():
    """A fresh DIRECT physics world with gravity and a floor plane; yields the client id."""
    client = p.connect(p.DIRECT)
    p.setGravity(0, 0, -9.81, physicsClientId=client)
    p.setTimeStep(DT, physicsClientId=client)
    floor = p.createCollisionShape(p.GEOM_PLANE, physicsClientId=client)
    p.createMultiBody(0, floor, physicsClientId=client)
    yield client
    p.disconnect(client)


def run(client, robots, seconds, dt=DT):
    """Step robots and physics together, as the world does."""
    robots = robots if isinstance(robots, list) else [robots]
    for _ in range(round(seconds / dt)):
        for r in robots:
            r.step(dt)
        p.stepSimulation(physicsClientId=client)


def add_box(client, pos, half, rgba=(1, 0, 0, 1)):
    col = p.createCollisionShape(p.GEOM_BOX, halfExtents=half, physicsClientId=client)
    vis = p.createVisualShape(p.GEOM_BOX, halfExtents=half, rgbaColor=rgba, physicsClientId=client)
    return p.createMultiBody(0, col, vis, basePosition=pos, physicsClientId=client)


def with_config(**sections):
    """CFG with some sections' fields replaced, e.g. battery={"initial": 0.5}."""
    update = {k: getattr(CFG, k).model_copy(update=v) if isinstance(v, dict) else v
              for k, v in sections.items()}
    return CFG.model_copy(update=update)


def camera_height(robot):
    return float(robot.camera.pose()[0][2])


def red_pixels(img):
    img = img.astype(int)
    return int(((img[..., 0] > 150) & (img[..., 1] < 80) & (img[..., 2] < 80)).sum())


# ------------------------------------------------------------------------------ URDF
def test_urdf_has_pepper_joints_limits_and_size(world):
    body = p.loadURDF(str(URDF_PATH), useFixedBase=True, physicsClientId=world)
    joints, links, mass = {}, set(), 0.0
    for j in range(p.getNumJoints(body, physicsClientId=world)):
        info = p.getJointInfo(body, j, physicsClientId=world)
        links.add(info[12].decode())
        mass += p.getDynamicsInfo(body, j, physicsClientId=world)[0]
        if info[2] == p.JOINT_REVOLUTE:
            joints[info[1].decode()] = (info[8], info[9], info[11])
    assert set(joints) == set(JOINT_NAMES)
    assert {"Head", "CameraTop_frame", "Tablet", "torso"} <= links
    assert joints["HeadYaw"][:2] == pytest.approx((-2.0857, 2.0857), abs=1e-3)
    assert joints["HeadPitch"][:2] == pytest.approx((-0.7069, 0.6370), abs=1e-3)
    assert joints["HipPitch"][:2] == pytest.approx((-1.0385, 1.0385), abs=1e-3)
    assert joints["KneePitch"][:2] == pytest.approx((-0.5149, 0.5149), abs=1e-3)
    assert joints["LShoulderRoll"][0] > 0 > joints["RShoulderRoll"][1]
    assert joints["LElbowRoll"][1] < 0 < joints["RElbowRoll"][0]
    assert joints["LWristYaw"][2] == pytest.approx(17.38, abs=0.01)
    assert 20.0 < mass < 35.0
    top = max(p.getAABB(body, j, physicsClientId=world)[1][2]
              for j in range(p.getNumJoints(body, physicsClientId=world)))
    assert 1.15 < top < 1.3


# ------------------------------------------------------------------------------ postures
def test_robot_stands_stable(world):
    robot = Robot(world, (0.5, -0.3, 0.4))
    height = camera_height(robot)
    run(world, robot, 3.0)
    assert robot.base.pose() == pytest.approx((0.5, -0.3, 0.4), abs=1e-9)
    assert robot.joints.posture == "Stand"
    assert robot.joints.posture_reached()
    stand = CFG.postures["Stand"]
    assert robot.joints.positions() == pytest.approx(stand, abs=0.02)
    assert camera_height(robot) == pytest.approx(height, abs=0.005)
    assert 1.05 < height < 1.25


def test_crouch_reaches_rest_angles_and_lowers_the_camera(world):
    robot = Robot(world)
    standing = camera_height(robot)
    robot.joints.set_posture("crouch")                          # case-insensitive
    assert not robot.joints.posture_reached()
    for _ in range(40):
        run(world, robot, 0.1)
        if robot.joints.posture_reached():
            break
    joints = robot.joints
    assert joints.posture_reached() and joints.posture == "Crouch" and joints.resting
    limits = robot.joints.limits()
    crouch = {n: float(np.clip(a, *limits[n])) for n, a in CFG.postures["Crouch"].items()}
    assert robot.joints.positions() == pytest.approx(crouch, abs=CFG.joints.position_tolerance)
    assert camera_height(robot) < standing - 0.15
    with pytest.raises(ValueError, match="unknown posture"):
        robot.joints.set_posture("Handstand")


def test_a_blocked_arm_is_named_off_target(world):
    robot = Robot(world)
    add_box(world, (0.32, -0.2, 0.95), (0.04, 0.2, 0.3))   # a shelf in front of the right arm
    run(world, robot, 0.5)
    assert robot.joints.posture_reached() and robot.joints.off_target() == {}
    robot.joints.move({"RShoulderPitch": -0.5}, 1.0)          # raise it forwards, into the shelf
    run(world, robot, 3.0)
    assert not robot.joints.posture_reached()
    off = robot.joints.off_target()
    assert list(off) == ["RShoulderPitch"] and off["RShoulderPitch"] > 0.5


def test_move_joints_respects_speed_and_limits(world):
    robot = Robot(world)
    vmax = dict(zip(JOINT_NAMES, robot.joints.max_velocity, strict=True))
    robot.joints.move({"HeadYaw": 1.5, "HeadPitch": 3.0}, speed=0.25)
    assert robot.joints.posture is None
    top = robot.joints.limits()["HeadPitch"][1]
    assert robot.joints.targets()["HeadPitch"] == pytest.approx(top)
    previous = robot.joints.positions()["HeadYaw"]
    fastest = 0.0
    for _ in range(24):                                  # 0.1 s
        run(world, robot, DT)
        now = robot.joints.positions()["HeadYaw"]
        fastest = max(fastest, (now - previous) / DT)
        previous = now
    assert fastest <= 0.25 * vmax["HeadYaw"] * 1.05
    assert previous == pytest.approx(0.25 * vmax["HeadYaw"] * 0.1, abs=0.03)
    run(world, robot, 1.0)
    assert robot.joints.posture_reached()
    got = robot.joints.positions()
    assert got["HeadYaw"] == pytest.approx(1.5, abs=0.02)
    assert got["HeadPitch"] == pytest.approx(0.637, abs=0.02)  # clamped to the upper limit
    with pytest.raises(ValueError, match="unknown joints"):
        robot.joints.move({"LeftEar": 0.1}, speed=0.5)
    with pytest.raises(ValueError, match="speed"):
        robot.joints.move({"HeadYaw": 0.0}, speed=1.5)


def test_the_head_looks_where_told_and_leaves_the_other_angle(world):
    robot = Robot(world)
    pitch = robot.head.targets()[1]
    robot.head.look(yaw=0.8, speed=0.5)                  # only the yaw moves
    assert robot.head.targets() == pytest.approx((0.8, pitch))
    robot.head.look(pitch=-0.3)
    run(world, robot, 2.0)
    assert robot.head.angles() == pytest.approx((0.8, -0.3), abs=0.02)
    lo, hi = robot.head.yaw_limits()
    robot.head.look(yaw=hi + 1.0)                        # clamped like any joint
    assert robot.head.targets()[0] == pytest.approx(hi) and lo < 0.0 < hi


def test_microphones_and_tablet_hand_over_each_input_once(world):
    robot = Robot(world)
    line = HeardLine(1, 0.0, "Anna", "Hello?", "robot", 0.0)
    thumb = FeedbackEvent(0.5, "Anna", 1, None)
    robot.tablet.touch(line)
    robot.tablet.touch(thumb)
    assert robot.tablet.inputs() == [line, thumb] and robot.tablet.inputs() == []
    assert robot.microphones.recordings() == []


# ------------------------------------------------------------------------------ base
def test_base_velocity_is_in_the_robot_frame(world):
    robot = Robot(world, (1.0, 1.0, math.pi / 2))        # facing +y
    robot.base.set_velocity(0.4, 0.0, 0.0)
    run(world, robot, 1.0)
    assert robot.base.pose() == pytest.approx((1.0, 1.4, math.pi / 2), abs=1e-6)
    robot.base.set_velocity(0.0, 0.3, 0.0)               # to its left: -x in the world
    run(world, robot, 1.0)
    assert robot.base.pose() == pytest.approx((0.7, 1.4, math.pi / 2), abs=1e-6)
    robot.base.set_velocity(0.0, 0.0, -1.0)
    run(world, robot, 1.0)
    assert robot.base.pose() == pytest.approx((0.7, 1.4, math.pi / 2 - 1.0), abs=1e-6)
    robot.base.set_velocity(3.0, 4.0, 9.0)               # clamped to the limits
    vx, vy, wz = robot.base.velocity
    assert math.hypot(vx, vy) == pytest.approx(CFG.base.max_linear_speed)
    assert vx / vy == pytest.approx(0.75) and wz == CFG.base.max_angular_speed


def test_a_wall_stops_the_base(world):
    wall = add_box(world, (1.5, 0.0, 0.5), (0.05, 2.0, 0.5))
    robot = Robot(world)
    robot.base.set_velocity(0.5, 0.0, 0.0)
    run(world, robot, 4.0)
    assert robot.base.blocked
    x = robot.base.pose()[0]
    assert 1.0 < x < 1.45 - 0.2                          # stopped in front of the wall
    gap = min(pt[8] for pt in p.getClosestPoints(robot.body_id, wall, 1.0, physicsClientId=world))
    assert 0.0 <= gap <= CFG.base.collision_margin + 0.01
    robot.base.set_velocity(0.0, 0.3, 0.0)               # sliding along the wall is allowed
    run(world, robot, 0.5)
    assert robot.base.pose()[:2] == pytest.approx((x, 0.15), abs=1e-6) and not robot.base.blocked
    robot.base.set_velocity(-0.3, 0.0, 0.0)              # and so is backing away
    run(world, robot, 1.0)
    assert robot.base.pose()[0] == pytest.approx(x - 0.3, abs=1e-6) and not robot.base.blocked


def test_walls_in_one_body_stop_the_base_in_a_corner(world):
    half = [[1.0, 0.05, 0.5], [0.05, 1.0, 0.5]]             # along y = 1 and x = 2
    col = p.createCollisionShapeArray([p.GEOM_BOX] * 2, halfExtents=half,
                                      collisionFramePositions=[[1.0, 1.0, 0.5], [2.0, 0.0, 0.5]],
                                      physicsClientId=world)
    p.createMultiBody(0, col, physicsClientId=world)
    robot = Robot(world, (0.0, 1.0 - 0.05 - 0.23 - 0.01, 0.0))  # base 1 cm from the wall
    robot.base.set_velocity(0.5, 0.0, 0.0)                    # along the first wall ...
    run(world, robot, 4.0)
    x, y, _ = robot.base.pose()
    assert robot.base.blocked and y == pytest.approx(0.71)         # ... into the second one
    assert 2.0 - 0.05 - 0.23 - CFG.base.collision_margin - 0.01 < x < 2.0 - 0.05 - 0.23


# ------------------------------------------------------------------------------ camera
def test_camera_sees_a_box_after_turning_towards_it(world):
    box = add_box(world, (0.0, 2.0, 0.9), (0.3, 0.3, 0.6))  # to the robot's left
    robot = Robot(world)
    before = robot.camera.frame()
    assert before.shape == (240, 320, 3) and before.dtype == np.uint8
    assert red_pixels(before) == 0
    robot.base.set_velocity(0.0, 0.0, 1.0)
    run(world, robot, math.pi / 2)
    assert robot.base.pose()[2] == pytest.approx(math.pi / 2, abs=0.01)
    rgb, mask = robot.camera.frame_with_segmentation()
    assert red_pixels(rgb) > 0.05 * 240 * 320
    assert mask.shape == (240, 320)
    bodies, links = decode_segmentation(mask)
    assert box in set(bodies.ravel().tolist())
    assert set(links[bodies == box].ravel().tolist()) == {-1}
    assert np.array_equal(rgb, robot.camera.frame())     # same view, same picture
    robot.camera.set_lighting({"lightAmbientCoeff": 0.1, "lightDiffuseCoeff": 0.2, "shadow": 0})
    assert robot.camera.frame().mean() < rgb.mean()      # the world's lighting is used


def test_decode_segmentation_splits_body_and_link():
    mask = np.array([[-1, 3, 3 + (5 << 24)]])
    bodies, links = decode_segmentation(mask)
    assert bodies.tolist() == [[-1, 3, 3]]
    assert links.tolist() == [[-1, -1, 4]]


# ------------------------------------------------------------------------------ battery
def test_battery_drains_faster_when_moving_and_rises_while_charging(world):
    cfg = with_config(battery={"initial": 0.5})
    idle = Robot(world, (0.0, 0.0, 0.0), cfg)
    busy = Robot(world, (0.0, 3.0, 0.0), cfg)
    busy.base.set_velocity(0.4, 0.0, 0.5)
    busy.joints.move({"LShoulderPitch": -1.0, "RShoulderPitch": -1.0}, speed=0.5)
    run(world, [idle, busy], 1.0)
    idle_drain, busy_drain = 0.5 - idle.battery.level, 0.5 - busy.battery.level
    expected = cfg.battery.idle_power_w * 1.0 / 3600 / cfg.battery.capacity_wh
    assert idle_drain == pytest.approx(expected, rel=1e-6)
    assert busy_drain > 1.5 * idle_drain
    idle.battery.start_charging()
    assert idle.battery.charging
    level = idle.battery.level
    run(world, idle, 1.0)
    assert idle.battery.level > level
    idle.battery.stop_charging()
    level = idle.battery.level
    run(world, idle, 0.5)
    assert not idle.battery.charging and idle.battery.level < level
    assert 0.0 <= busy.battery.level <= 1.0


# ------------------------------------------------------------------------------ heat
def test_motor_temperature_heats_cools_and_trips_overheat(world):
    cfg = with_config(thermal={"overheat_c": 28.0, "overheat_clear_c": 26.0})
    robot = Robot(world, config=cfg)
    ambient = cfg.thermal.ambient_c
    run(world, robot, 0.5)
    assert robot.thermal.temperature == pytest.approx(ambient)   # standing still: no heating
    up = {"LShoulderPitch": -1.0, "RShoulderPitch": -1.0, "LElbowYaw": 1.0, "RElbowYaw": -1.0}
    down = dict.fromkeys(up, 0.0) | {"LShoulderPitch": 1.5, "RShoulderPitch": 1.5}
    for i in range(6):                                   # wave the arms at full speed
        robot.joints.move(up if i % 2 == 0 else down, speed=1.0)
        run(world, robot, 0.25)
    assert robot.thermal.temperature > 28.0 and robot.thermal.overheated
    robot.joints.set_posture("Crouch")
    run(world, robot, 1.5)
    hot = robot.thermal.temperature
    for _ in range(90):                                  # rest (no physics needed for heat)
        robot.step(1.0)
    assert robot.joints.resting and robot.thermal.temperature < hot
    assert robot.thermal.temperature <= 26.0 and not robot.thermal.overheated


def test_cooling_is_faster_in_the_rest_posture(world):
    hot = {"initial_c": 45.0}
    standing = Robot(world, (0.0, 0.0, 0.0), with_config(thermal=hot))
    resting = Robot(world, (0.0, 3.0, 0.0), with_config(thermal=hot, initial_posture="Crouch"))
    for _ in range(20):
        standing.step(0.5)
        resting.step(0.5)
    assert not standing.joints.resting and resting.joints.resting
    assert CFG.thermal.ambient_c < resting.thermal.temperature < standing.thermal.temperature < 45.0


def test_motor_heat_model_is_exact_for_any_step():
    model_a, model_b = MotorHeat(CFG.thermal), MotorHeat(CFG.thermal)
    model_a.temperature = model_b.temperature = 50.0
    model_a.update(10.0, 0.0, 0.0, 0.0, resting=False)
    for _ in range(100):
        model_b.update(0.1, 0.0, 0.0, 0.0, resting=False)
    assert model_a.temperature == pytest.approx(model_b.temperature)
    excess = 25.0 * math.exp(-10.0 / CFG.thermal.cooling_tau_s)
    assert model_a.temperature == pytest.approx(CFG.thermal.ambient_c + excess)
