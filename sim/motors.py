"""The simulated joint motors: named joints moved on ramps towards postures or targets,
PyBullet position motors following the ramps (docs/robot.md)."""

from __future__ import annotations

import numpy as np
import pybullet as p

from robot.joints import JOINT_NAMES
from sim.robot_config import RobotConfig


def ramp(current: np.ndarray, target: np.ndarray, max_step: np.ndarray) -> np.ndarray:
    """Move ``current`` towards ``target`` by at most ``max_step`` (element-wise)."""
    return current + np.clip(target - current, -max_step, max_step)


class SimJoints:
    """The joints of the robot body ``body`` (:class:`robot.body.Joints`), whose PyBullet
    joint indices in :data:`JOINT_NAMES` order are ``joint_ids``; starts in the config's
    initial posture. Attributes ``lower``, ``upper`` (rad) and ``max_velocity`` (rad/s) per
    joint come from the URDF."""

    def __init__(self, client: int, body: int, joint_ids: list[int], cfg: RobotConfig) -> None:
        self.client, self.body, self.cfg = client, body, cfg
        self._joint_ids = joint_ids
        info = np.array([p.getJointInfo(body, j, physicsClientId=client)[8:12]
                         for j in joint_ids])
        self.lower, self.upper, effort, self.max_velocity = info.T
        self._forces = list(effort * cfg.joints.force_scale)
        start = self._posture_vector(cfg.initial_posture, np.zeros(len(JOINT_NAMES)))
        for j, q in zip(joint_ids, start, strict=True):
            p.resetJointState(body, j, float(q), physicsClientId=client)
        self._setpoint = start.copy()             # where the motors are told to be now
        self._target = start.copy()               # where the ramps end
        self._speed = np.ones(len(JOINT_NAMES))   # fraction of max velocity, per joint
        self.velocity = np.zeros(len(JOINT_NAMES))
        self._posture: str | None = cfg.initial_posture
        self._held = self._setpoint
        self._send_motor_commands(self._setpoint, self.velocity)

    @property
    def names(self) -> tuple[str, ...]:
        """The 15 actuated joints, in a fixed order."""
        return JOINT_NAMES

    @property
    def postures(self) -> tuple[str, ...]:
        """Names of the postures defined in the config."""
        return tuple(self.cfg.postures)

    def limits(self) -> dict[str, tuple[float, float]]:
        """(lower, upper) limit of every joint, in rad."""
        return {n: (float(lo), float(hi))
                for n, lo, hi in zip(JOINT_NAMES, self.lower, self.upper, strict=True)}

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
        """The posture last asked for, or None after :meth:`move` changed a joint."""
        return self._posture

    def move(self, targets: dict[str, float], speed: float) -> None:
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

    def set_positions(self, angles: dict[str, float]) -> None:
        """Teleport the named joints to ``angles`` (rad, clamped to the limits) with no ramp
        and hold them there, e.g. to pose the head for a rendered frame."""
        self.move(angles, 1.0)
        self._setpoint = self._setpoint.copy()
        for name in angles:
            i = JOINT_NAMES.index(name)
            self._setpoint[i] = self._target[i]
            p.resetJointState(self.body, self._joint_ids[i], float(self._target[i]),
                              physicsClientId=self.client)
        self._held = self._setpoint
        self.velocity = np.zeros(len(JOINT_NAMES))
        self._send_motor_commands(self._setpoint, self.velocity)

    def positions(self) -> dict[str, float]:
        """Measured angle of every joint, in rad."""
        states = p.getJointStates(self.body, self._joint_ids, physicsClientId=self.client)
        return {n: float(s[0]) for n, s in zip(JOINT_NAMES, states, strict=True)}

    def targets(self) -> dict[str, float]:
        """Where every joint is heading (after clamping to its limits), in rad."""
        return {n: float(t) for n, t in zip(JOINT_NAMES, self._target, strict=True)}

    def posture_reached(self) -> bool:
        """True once every joint's ramp has ended and its measured angle is within
        ``position_tolerance`` of its target (the posture or the move_joints targets)."""
        return np.array_equal(self._setpoint, self._target) and not self.off_target()

    def off_target(self) -> dict[str, float]:
        """The joints whose measured angle is farther than ``position_tolerance`` from
        their target, with that error (rad, measured - target)."""
        error = np.array(list(self.positions().values())) - self._target
        return {name: round(float(e), 3) for name, e in zip(JOINT_NAMES, error, strict=True)
                if abs(e) > self.cfg.joints.position_tolerance}

    def advance(self, dt: float) -> None:
        """Move the set-points along their ramps and command the motors to follow."""
        previous = self._setpoint
        self._setpoint = ramp(previous, self._target, self._speed * self.max_velocity * dt)
        self.velocity = (self._setpoint - previous) / dt
        if np.any(self.velocity) or not np.array_equal(previous, self._held):
            self._send_motor_commands(previous, self.velocity)
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
            p.setJointMotorControl2(self.body, j, p.POSITION_CONTROL, targetPosition=float(q),
                                    targetVelocity=float(v), force=force, positionGain=gain,
                                    velocityGain=1.0, maxVelocity=float(vmax),
                                    physicsClientId=self.client)

    def fail(self, name: str, failed: bool = True) -> None:
        """Cut the motor torque of joint ``name`` to 0 (or give it back)."""
        i = JOINT_NAMES.index(name)
        effort = p.getJointInfo(self.body, self._joint_ids[i], physicsClientId=self.client)[10]
        self._forces[i] = 0.0 if failed else effort * self.cfg.joints.force_scale
        self._send_motor_commands(self._held, self.velocity)

    def tracking_errors(self) -> dict[str, float]:
        """|measured - commanded| angle per joint (rad): large for a joint that can't follow."""
        measured = np.array(list(self.positions().values()))
        return dict(zip(JOINT_NAMES, np.abs(measured - self._setpoint).round(3).tolist(),
                        strict=True))

    @property
    def resting(self) -> bool:
        """True while the joints are commanded to the rest posture (faster cooling)."""
        rest = self._posture_vector(self.cfg.thermal.rest_posture, self._setpoint)
        return bool(np.all(np.abs(self._setpoint - rest) <= self.cfg.joints.position_tolerance))
