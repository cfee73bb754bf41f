"""The simulated Pepper-like robot: named joints and postures, an omnidirectional base,
the forehead camera, the battery and the motor temperature.

In the spirit of qiBullet, :class:`Robot` hides PyBullet ids behind joint and posture
names. The world owns the physics: it calls :meth:`Robot.step` once per simulation step
(before ``stepSimulation``) and the robot advances its base, joint ramps, battery and
motor temperature by ``dt``. Joint limits come from the URDF, every other number from
``config/robot.yaml``; docs/robot.md describes the models.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from functools import partial
from pathlib import Path
from typing import Any

import numpy as np
import pybullet as p

from core.paths import URDF_DIR
from robot.geometry import wrap_angle
from robot.joints import JOINT_NAMES
from sim.lasers import LaserScanners
from sim.power import Battery, MotorHeat
from sim.render import Buffers, tiny_render
from sim.robot_config import RobotConfig, load_robot_config

URDF_PATH = URDF_DIR / "pepper.urdf"
CAMERA_LINK = "CameraTop_frame"
Pose = tuple[float, float, float]


# ---------------------------------------------------------------------------- helpers
def yaw_quaternion(yaw: float) -> tuple[float, float, float, float]:
    """Quaternion (x, y, z, w) of a rotation by ``yaw`` about the vertical axis."""
    return (0.0, 0.0, math.sin(yaw / 2.0), math.cos(yaw / 2.0))


def ramp(current: np.ndarray, target: np.ndarray, max_step: np.ndarray) -> np.ndarray:
    """Move ``current`` towards ``target`` by at most ``max_step`` (element-wise)."""
    return current + np.clip(target - current, -max_step, max_step)


def decode_segmentation(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Split a mask rendered with ``ER_SEGMENTATION_MASK_OBJECT_AND_LINKINDEX`` into body
    ids and link indices (the base is link -1; background is body -1, link -1)."""
    mask = np.asarray(mask, dtype=np.int64)
    background = mask < 0
    bodies = np.where(background, -1, mask & ((1 << 24) - 1))
    links = np.where(background, -1, (mask >> 24) - 1)
    return bodies, links


def bodies_near(client: int, body: int, centre: tuple[float, float], distance: float,
                angle: float, margin: float) -> set[int]:
    """Other bodies whose bounding boxes come within ``margin`` of the bounding box of
    ``body`` grown by what a move of ``distance`` and a turn of ``angle`` about
    ``centre`` can sweep."""
    boxes = [p.getAABB(body, link, physicsClientId=client)
             for link in range(-1, p.getNumJoints(body, physicsClientId=client))]
    low = np.min([b[0] for b in boxes], axis=0)
    high = np.max([b[1] for b in boxes], axis=0)
    c = np.asarray(centre)
    radius = float(np.hypot(*np.maximum(np.abs(low[:2] - c), np.abs(high[:2] - c))))
    pad = distance + angle * radius + margin
    found = p.getOverlappingObjects((low - pad).tolist(), (high + pad).tolist(),
                                    physicsClientId=client)
    return {b for b, _ in found or ()} - {body}


def moves_into(points: list[tuple], centre: tuple[float, float], dx: float, dy: float,
               dyaw: float) -> bool:
    """True when a move by (dx, dy, dyaw) about ``centre`` carries any of the robot's
    closest ``points`` (from ``getClosestPoints(robot, other)`` after the move) towards
    the other body, i.e. against the contact normal. Sliding along and leaving are fine."""
    for pt in points:
        rx, ry = pt[5][0] - centre[0], pt[5][1] - centre[1]     # the point on the robot
        ux, uy = dx - dyaw * ry, dy + dyaw * rx                 # its displacement
        if ux * pt[7][0] + uy * pt[7][1] < -1e-9:               # normal points B -> robot
            return True
    return False


# ---------------------------------------------------------------------------- robot
class Robot:
    """A Pepper-like robot in one PyBullet world, addressed by joint and posture names.

    Attributes: ``body_id`` (the PyBullet body), ``client``, ``cfg`` (the RobotConfig),
    and per joint in :data:`JOINT_NAMES` order ``lower``, ``upper`` (rad) and
    ``max_velocity`` (rad/s) from the URDF.
    """

    def __init__(self, client: int, pose: Pose = (0.0, 0.0, 0.0),
                 config: RobotConfig | None = None, urdf: str | Path = URDF_PATH) -> None:
        """Load the robot into the world ``client`` (a PyBullet physicsClientId) at
        ``pose`` = (x, y, yaw) on the floor, in the config's initial posture."""
        self.cfg = config or load_robot_config()
        self.client = client
        x, y, yaw = pose
        self.body_id = p.loadURDF(str(urdf), [x, y, 0.0], yaw_quaternion(yaw), useFixedBase=True,
                                  flags=p.URDF_USE_INERTIA_FROM_FILE, physicsClientId=client)
        self._links, joints = self._index_links()
        missing = set(JOINT_NAMES) - set(joints)
        if missing:
            raise ValueError(f"{urdf} lacks the joints {sorted(missing)}")
        self._joint_ids = [joints[n] for n in JOINT_NAMES]
        info = np.array([p.getJointInfo(self.body_id, j, physicsClientId=client)[8:12]
                         for j in self._joint_ids])
        self.lower, self.upper, effort, self.max_velocity = info.T
        self._forces = list(effort * self.cfg.joints.force_scale)

        start = self._posture_vector(self.cfg.initial_posture, np.zeros(len(JOINT_NAMES)))
        for j, q in zip(self._joint_ids, start, strict=True):
            p.resetJointState(self.body_id, j, float(q), physicsClientId=client)
        self._setpoint = start.copy()             # where the motors are told to be now
        self._target = start.copy()               # where the ramps end
        self._speed = np.ones(len(JOINT_NAMES))   # fraction of max velocity, per joint
        self._joint_velocity = np.zeros(len(JOINT_NAMES))
        self._posture: str | None = self.cfg.initial_posture
        self._command = (0.0, 0.0, 0.0)
        self._blocked = False
        self._battery = Battery(self.cfg.battery)
        self._heat = MotorHeat(self.cfg.thermal)
        self._light: dict[str, Any] = {}
        #: draws the head camera's frames (sim/split_render.py): TinyRenderer here, or a
        #: :class:`~sim.split_render.SplitRenderer` sharing the work with a helper process
        self.renderer: Callable[..., Buffers] = partial(tiny_render, client)
        self._camera_fault: str | None = None
        self._last_render: dict[tuple[int, int], tuple[np.ndarray, np.ndarray, np.ndarray]] = {}
        self.frame_seq = 0   # sequence number of the camera's frames (a frozen camera repeats)
        #: the base's laser scanners (sim/lasers.py)
        self.lasers = LaserScanners(client, self.body_id, self.cfg.lasers, self.pose)
        self._held = self._setpoint
        self._send_motor_commands(self._setpoint, self._joint_velocity)

    def _index_links(self) -> tuple[dict[str, int], dict[str, int]]:
        """Link name -> index and revolute joint name -> index, from the loaded URDF."""
        links, joints = {}, {}
        for j in range(p.getNumJoints(self.body_id, physicsClientId=self.client)):
            info = p.getJointInfo(self.body_id, j, physicsClientId=self.client)
            links[info[12].decode()] = j
            if info[2] == p.JOINT_REVOLUTE:
                joints[info[1].decode()] = j
        return links, joints

    # -- names ---------------------------------------------------------------------------
    @property
    def joint_names(self) -> tuple[str, ...]:
        """The 15 actuated joints, in a fixed order."""
        return JOINT_NAMES

    @property
    def postures(self) -> tuple[str, ...]:
        """Names of the postures defined in the config."""
        return tuple(self.cfg.postures)

    def link_index(self, name: str) -> int:
        """PyBullet link index of a link named in the URDF (e.g. "Head", "Tablet")."""
        if name not in self._links:
            raise ValueError(f"unknown link {name!r}; known: {sorted(self._links)}")
        return self._links[name]

    def joint_limits(self) -> dict[str, tuple[float, float]]:
        """(lower, upper) limit of every joint, in rad."""
        return {n: (float(lo), float(hi))
                for n, lo, hi in zip(JOINT_NAMES, self.lower, self.upper, strict=True)}

    # -- joints and postures -------------------------------------------------------------
    def _posture_vector(self, name: str, fallback: np.ndarray) -> np.ndarray:
        angles = self.cfg.postures[name]
        vec = np.array([angles.get(n, f) for n, f in zip(JOINT_NAMES, fallback, strict=True)])
        return np.clip(vec, self.lower, self.upper)

    def _posture_name(self, name: str) -> str:
        for known in self.cfg.postures:
            if known.lower() == name.lower():
                return known
        raise ValueError(f"unknown posture {name!r}; known: {list(self.cfg.postures)}")

    @staticmethod
    def _check_speed(speed: float) -> float:
        if not 0.0 < speed <= 1.0:
            raise ValueError(f"speed is a fraction of the maximum in (0, 1], got {speed}")
        return speed

    def set_posture(self, name: str, speed: float | None = None) -> None:
        """Start moving every joint of posture ``name`` (case-insensitive) towards it at
        ``speed`` x the joint speed limits (default: ``posture_speed`` from the config)."""
        name = self._posture_name(name)
        speed = self._check_speed(self.cfg.posture_speed if speed is None else speed)
        self._target = self._posture_vector(name, self._target)
        self._speed[:] = speed
        self._posture = name

    @property
    def posture(self) -> str | None:
        """The posture last asked for, or None after :meth:`move_joints` changed a joint."""
        return self._posture

    def move_joints(self, targets: dict[str, float], speed: float) -> None:
        """Move the named joints towards ``targets`` (rad, clamped to the joint limits) at
        ``speed`` x their speed limits. Raises ValueError for an unknown joint name."""
        unknown = sorted(set(targets) - set(JOINT_NAMES))
        if unknown:
            raise ValueError(f"unknown joints {unknown}; known: {list(JOINT_NAMES)}")
        speed = self._check_speed(speed)
        for name, angle in targets.items():
            i = JOINT_NAMES.index(name)
            self._target[i] = min(max(float(angle), self.lower[i]), self.upper[i])
            self._speed[i] = speed
        if targets:
            self._posture = None

    def set_joint_positions(self, angles: dict[str, float]) -> None:
        """Teleport the named joints to ``angles`` (rad, clamped to the limits) with no ramp
        and hold them there, e.g. to pose the head for a rendered frame."""
        self.move_joints(angles, 1.0)
        self._setpoint = self._setpoint.copy()
        for name in angles:
            i = JOINT_NAMES.index(name)
            self._setpoint[i] = self._target[i]
            p.resetJointState(self.body_id, self._joint_ids[i], float(self._target[i]),
                              physicsClientId=self.client)
        self._held = self._setpoint
        self._joint_velocity = np.zeros(len(JOINT_NAMES))
        self._send_motor_commands(self._setpoint, self._joint_velocity)

    def joint_positions(self) -> dict[str, float]:
        """Measured angle of every joint, in rad."""
        states = p.getJointStates(self.body_id, self._joint_ids, physicsClientId=self.client)
        return {n: float(s[0]) for n, s in zip(JOINT_NAMES, states, strict=True)}

    def joint_targets(self) -> dict[str, float]:
        """Where every joint is heading (after clamping to its limits), in rad."""
        return {n: float(t) for n, t in zip(JOINT_NAMES, self._target, strict=True)}

    def posture_reached(self) -> bool:
        """True once every joint's ramp has ended and its measured angle is within
        ``position_tolerance`` of its target (the posture or the move_joints targets)."""
        return np.array_equal(self._setpoint, self._target) and not self.joints_off_target()

    def joints_off_target(self) -> dict[str, float]:
        """The joints whose measured angle is farther than ``position_tolerance`` from
        their target, with that error (rad, measured - target)."""
        error = np.array(list(self.joint_positions().values())) - self._target
        return {name: round(float(e), 3) for name, e in zip(JOINT_NAMES, error, strict=True)
                if abs(e) > self.cfg.joints.position_tolerance}

    def _advance_joints(self, dt: float) -> None:
        """Move the set-points along their ramps and command the motors to follow."""
        previous = self._setpoint
        self._setpoint = ramp(previous, self._target, self._speed * self.max_velocity * dt)
        self._joint_velocity = (self._setpoint - previous) / dt
        if np.any(self._joint_velocity) or not np.array_equal(previous, self._held):
            self._send_motor_commands(previous, self._joint_velocity)
            self._held = previous   # motor commands persist: resend only on a change

    def _send_motor_commands(self, positions: np.ndarray, velocities: np.ndarray) -> None:
        """Position motors: feed-forward ramp velocity plus a proportional pull towards
        the ramp's position at the start of the step, capped at the URDF speed limits and
        the (scaled) URDF efforts."""
        c = self.cfg.joints
        physics_dt = p.getPhysicsEngineParameters(physicsClientId=self.client)["fixedTimeStep"]
        gain = min(1.0, c.position_gain_per_s * physics_dt)
        for j, q, v, force, vmax in zip(self._joint_ids, positions, velocities, self._forces,
                                        self.max_velocity, strict=True):
            p.setJointMotorControl2(self.body_id, j, p.POSITION_CONTROL, targetPosition=float(q),
                                    targetVelocity=float(v), force=force, positionGain=gain,
                                    velocityGain=1.0, maxVelocity=float(vmax),
                                    physicsClientId=self.client)

    # -- base ----------------------------------------------------------------------------
    def set_base_velocity(self, vx: float, vy: float, wz: float) -> None:
        """Drive at (vx, vy) m/s in the robot's frame (x forward, y left) while turning at
        wz rad/s (counter-clockwise). The speed is clamped to the config's limits and the
        command holds until changed."""
        c = self.cfg.base
        speed = math.hypot(vx, vy)
        scale = min(1.0, c.max_linear_speed / speed) if speed > 0 else 0.0
        wz = min(max(wz, -c.max_angular_speed), c.max_angular_speed)
        self._command = (vx * scale, vy * scale, wz)

    def stop(self) -> None:
        """Stop the base."""
        self._command = (0.0, 0.0, 0.0)

    @property
    def base_velocity(self) -> tuple[float, float, float]:
        """The clamped (vx, vy, wz) command in force."""
        return self._command

    @property
    def blocked(self) -> bool:
        """True when an obstacle stopped (part of) the base motion in the last step."""
        return self._blocked

    def pose(self) -> Pose:
        """(x, y, yaw) of the base on the floor, in the world frame (m, m, rad)."""
        pos, orn = p.getBasePositionAndOrientation(self.body_id, physicsClientId=self.client)
        yaw = p.getEulerFromQuaternion(orn, physicsClientId=self.client)[2]
        return float(pos[0]), float(pos[1]), float(yaw)

    def set_pose(self, x: float, y: float, yaw: float) -> None:
        """Teleport the base (no collision check), e.g. when a scenario starts."""
        p.resetBasePositionAndOrientation(self.body_id, [x, y, 0.0], yaw_quaternion(yaw),
                                          physicsClientId=self.client)

    def _advance_base(self, dt: float) -> tuple[float, float]:
        """Integrate the command over ``dt`` in collision-checked pieces; returns the
        distance driven and the angle turned. A piece the obstacles refuse is retried as
        pure translation, then as pure rotation; if all are refused the base stops."""
        vx, vy, wz = self._command
        self._blocked = False
        if vx == vy == wz == 0.0:
            return 0.0, 0.0
        c = self.cfg.base
        pieces = max(1, math.ceil(max(math.hypot(vx, vy) * dt / c.collision_step,
                                      abs(wz) * dt / c.collision_turn_step)))
        h = dt / pieces
        driven = turned = 0.0
        for _ in range(pieces):
            x, y, yaw = self.pose()
            heading = yaw + wz * h / 2.0    # midpoint rule: exact arcs in the limit
            dx = (vx * math.cos(heading) - vy * math.sin(heading)) * h
            dy = (vx * math.sin(heading) + vy * math.cos(heading)) * h
            full = (dx, dy, wz * h)
            tries = [m for m in dict.fromkeys([full, (dx, dy, 0.0), (0.0, 0.0, wz * h)]) if any(m)]
            moved = next((m for m in tries if self._try_move(x, y, yaw, *m)), None)
            self._blocked = self._blocked or moved != full
            if moved is None:
                break
            driven += math.hypot(moved[0], moved[1])
            turned += abs(moved[2])
        return driven, turned

    def _try_move(self, x: float, y: float, yaw: float, dx: float, dy: float,
                  dyaw: float) -> bool:
        """Move from (x, y, yaw) by (dx, dy, dyaw) unless, at the new pose, a point of
        the robot within the collision margin of another body is moving into it; returns
        whether it moved."""
        margin = self.cfg.base.collision_margin
        nearby = bodies_near(self.client, self.body_id, (x, y), math.hypot(dx, dy), abs(dyaw),
                             margin)
        self.set_pose(x + dx, y + dy, wrap_angle(yaw + dyaw))
        for other in nearby:
            points = p.getClosestPoints(self.body_id, other, margin, physicsClientId=self.client)
            if moves_into(points or [], (x + dx, y + dy), dx, dy, dyaw):
                self.set_pose(x, y, yaw)
                return False
        return True

    # -- camera --------------------------------------------------------------------------
    def camera_pose(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """World position, optical axis (unit) and image-up vector of the head camera."""
        state = p.getLinkState(self.body_id, self._links[CAMERA_LINK],
                               computeForwardKinematics=True, physicsClientId=self.client)
        rot = np.array(p.getMatrixFromQuaternion(state[5], physicsClientId=self.client))
        rot = rot.reshape(3, 3)
        return np.array(state[4]), rot[:, 0], rot[:, 2]

    def head_yaw(self) -> float:
        """Where the head faces on the floor (rad, world frame): its camera's axis."""
        axis = self.camera_pose()[1]
        return math.atan2(float(axis[1]), float(axis[0]))

    def camera_matrices(self, width: int, height: int) -> tuple[list[float], list[float]]:
        """The head camera's OpenGL view and projection matrices (column-major) for a
        ``width`` x ``height`` frame, as ``getCameraImage`` takes them."""
        eye, forward, up = self.camera_pose()
        cam = self.cfg.camera
        view = p.computeViewMatrix(eye.tolist(), (eye + forward).tolist(), up.tolist(),
                                   physicsClientId=self.client)
        proj = p.computeProjectionMatrixFOV(cam.fov_deg, width / height, cam.near, cam.far,
                                            physicsClientId=self.client)
        return view, proj

    def body_at_pixel(self, u: float, v: float, width: int, height: int) -> int | None:
        """The body the head camera sees at pixel ``(u, v)`` of a ``width`` x ``height``
        frame: a ray cast along that pixel's line of sight (None: nothing, or the robot)."""
        eye, forward, up = self.camera_pose()
        half = math.tan(math.radians(self.cfg.camera.fov_deg) / 2)
        x = (2 * (u + 0.5) / width - 1) * half * width / height
        y = (1 - 2 * (v + 0.5) / height) * half
        ray = forward + x * np.cross(forward, up) + y * up
        ray /= np.linalg.norm(ray)
        hit = p.rayTest((eye + 0.05 * ray).tolist(), (eye + self.cfg.camera.far * ray).tolist(),
                        physicsClientId=self.client)[0][0]
        return hit if hit >= 0 and hit != self.body_id else None

    def _render(self, width: int, height: int, flags: int
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        cam = self.cfg.camera
        view, proj = self.camera_matrices(width, height)
        rgba, z, seg = self.renderer(width, height, view, proj, flags, self._light)
        rgb = rgba[..., :3].copy()
        # OpenGL depth buffer in [0, 1] -> distance along the optical axis (m)
        depth = cam.far * cam.near / (cam.far - (cam.far - cam.near) * z)
        if self._camera_fault == "black":
            rgb[:] = 0
        self.frame_seq += 1
        render = (rgb, seg, depth)
        self._last_render[width, height] = render
        return render

    def _frame(self, width: int, height: int, flags: int
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """A new render, or the last one again while the camera is frozen."""
        if self._camera_fault == "frozen" and (width, height) in self._last_render:
            return self._last_render[width, height]
        return self._render(width, height, flags)

    # -- faults (``companion run --faults``, docs/reliability.md) -----------------------------
    def set_camera_fault(self, mode: str | None) -> None:
        """``"black"``: black colour frames; ``"frozen"``: the last frame again, with its
        sequence number (:attr:`frame_seq`); None: the camera works."""
        self._camera_fault = mode

    def fail_joint(self, name: str, failed: bool = True) -> None:
        """Cut the motor torque of joint ``name`` to 0 (or give it back)."""
        i = JOINT_NAMES.index(name)
        effort = p.getJointInfo(self.body_id, self._joint_ids[i], physicsClientId=self.client)[10]
        self._forces[i] = 0.0 if failed else effort * self.cfg.joints.force_scale
        self._send_motor_commands(self._held, self._joint_velocity)

    def tracking_errors(self) -> dict[str, float]:
        """|measured - commanded| angle per joint (rad): large for a joint that can't follow."""
        measured = np.array(list(self.joint_positions().values()))
        return dict(zip(JOINT_NAMES, np.abs(measured - self._setpoint).round(3).tolist(),
                        strict=True))

    def set_lighting(self, light: Mapping[str, Any]) -> None:
        """TinyRenderer lighting for the camera: keyword arguments of ``getCameraImage``
        such as ``lightDirection`` or ``shadow`` (e.g. the world's
        ``Light.camera_kwargs()``); an empty mapping restores PyBullet's defaults."""
        self._light = dict(light)

    def camera_frame(self, width: int = 320, height: int = 240) -> np.ndarray:
        """RGB image (height, width, 3) uint8 from the head camera (TinyRenderer)."""
        return self._frame(width, height, p.ER_NO_SEGMENTATION_MASK)[0]

    def camera_frame_with_depth(self, width: int = 320, height: int = 240,
                                ) -> tuple[np.ndarray, np.ndarray]:
        """RGB image and the (height, width) float32 depth image of the same view: each
        pixel's distance along the optical axis in metres (Pepper's 3D camera; the same
        render, so it costs nothing extra)."""
        rgb, _, depth = self._frame(width, height, p.ER_NO_SEGMENTATION_MASK)
        return rgb, depth

    def camera_frame_with_segmentation(self, width: int = 320, height: int = 240,
                                       ) -> tuple[np.ndarray, np.ndarray]:
        """RGB image and the (height, width) int32 segmentation mask. Each mask value is
        ``body_id + ((link_index + 1) << 24)``, -1 for background; see
        :func:`decode_segmentation`."""
        return self._frame(width, height, p.ER_SEGMENTATION_MASK_OBJECT_AND_LINKINDEX)[:2]

    # -- battery and temperature ---------------------------------------------------------
    @property
    def battery(self) -> float:
        """State of charge in [0, 1]."""
        return self._battery.level

    def set_battery(self, level: float) -> None:
        """Set the state of charge (a household run keeps it equal to 1 - energy drive)."""
        if not 0.0 <= level <= 1.0:
            raise ValueError(f"battery level must lie in [0, 1], got {level}")
        self._battery.level = float(level)

    @property
    def charging(self) -> bool:
        """True between :meth:`start_charging` and :meth:`stop_charging` (docked)."""
        return self._battery.charging

    def start_charging(self) -> None:
        """Plug the charger in (the world decides when the robot is docked)."""
        self._battery.charging = True

    def stop_charging(self) -> None:
        """Unplug the charger."""
        self._battery.charging = False

    @property
    def motor_temperature(self) -> float:
        """Lumped motor temperature in degrees C."""
        return self._heat.temperature

    @property
    def overheated(self) -> bool:
        """True from ``overheat_c`` up until the motors cool to ``overheat_clear_c``."""
        return self._heat.overheated

    @property
    def resting(self) -> bool:
        """True while the joints are commanded to the rest posture (faster cooling)."""
        rest = self._posture_vector(self.cfg.thermal.rest_posture, self._setpoint)
        return bool(np.all(np.abs(self._setpoint - rest) <= self.cfg.joints.position_tolerance))

    # -- the step ------------------------------------------------------------------------
    def step(self, dt: float) -> None:
        """Advance base motion, joint ramps, battery and motor temperature by ``dt``
        seconds. Call once per simulation step, before ``stepSimulation``."""
        if dt <= 0:
            raise ValueError(f"dt must be positive, got {dt}")
        driven, turned = self._advance_base(dt)
        self._advance_joints(dt)
        joint_speed = float(np.abs(self._joint_velocity).sum())
        self._battery.update(dt, driven / dt, turned / dt, joint_speed)
        self._heat.update(dt, driven / dt, turned / dt, joint_speed, self.resting)
