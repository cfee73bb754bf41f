"""The simulated Pepper-like robot: a body of named parts on PyBullet.

In the spirit of qiBullet, :class:`Robot` hides PyBullet ids behind parts with names: the
``base`` (sim/base.py), the ``joints`` and their postures (sim/motors.py) with the ``head``'s
gaze on them (robot/head.py), the forehead
``camera`` (sim/head_camera.py), the base's ``lasers`` (sim/lasers.py), the ``battery`` and
the motors' ``thermal`` state (sim/power.py), the ``microphones`` and the ``tablet``
(sim/inputs.py); each implements its interface in robot/body.py. The world owns the
physics: it calls :meth:`Robot.step` once per simulation step (before ``stepSimulation``)
and the robot advances its base, joint ramps, battery and motor temperature by ``dt``.
Joint limits come from the URDF, every other number from ``config/robot.yaml``;
docs/robot.md describes the models.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np
import pybullet as p

from core.paths import URDF_DIR
from robot.body import Pose
from robot.head import JointHead
from robot.joints import JOINT_NAMES
from sim.base import SimBase, yaw_quaternion
from sim.head_camera import SimCamera
from sim.inputs import SimMicrophones, SimTablet
from sim.lasers import LaserScanners
from sim.motors import SimJoints
from sim.power import Battery, MotorHeat
from sim.robot_config import RobotConfig, load_robot_config

URDF_PATH = URDF_DIR / "pepper.urdf"
CAMERA_LINK = "CameraTop_frame"


class Robot:
    """A Pepper-like robot in one PyBullet world (:class:`robot.body.Body`).

    Attributes: the parts ``base``, ``joints``, ``head``, ``camera``, ``lasers``, ``battery``,
    ``thermal``, ``microphones`` and ``tablet``; ``body_id`` (the PyBullet body),
    ``client`` and ``cfg`` (the RobotConfig).
    """

    def __init__(self, client: int, pose: Pose = (0.0, 0.0, 0.0),
                 config: RobotConfig | None = None, urdf: str | Path = URDF_PATH,
                 faces: Callable[[int], str | None] = lambda body: None) -> None:
        """Load the robot into the world ``client`` (a PyBullet physicsClientId) at
        ``pose`` = (x, y, yaw) on the floor, in the config's initial posture; ``faces``
        gives the expression on the face of a body (the world's people)."""
        self.cfg = config or load_robot_config()
        self.client = client
        x, y, yaw = pose
        self.body_id = p.loadURDF(str(urdf), [x, y, 0.0], yaw_quaternion(yaw), useFixedBase=True,
                                  flags=p.URDF_USE_INERTIA_FROM_FILE, physicsClientId=client)
        self._links, joints = self._index_links()
        missing = set(JOINT_NAMES) - set(joints)
        if missing:
            raise ValueError(f"{urdf} lacks the joints {sorted(missing)}")
        self.joints = SimJoints(client, self.body_id, [joints[n] for n in JOINT_NAMES],
                                self.cfg)
        self.head = JointHead(self.joints)
        self.base = SimBase(client, self.body_id, self.cfg.base)
        self.battery = Battery(self.cfg.battery)
        self.thermal = MotorHeat(self.cfg.thermal)
        self.camera = SimCamera(client, self.body_id, self._links[CAMERA_LINK],
                                self.cfg.camera, faces)
        self.lasers = LaserScanners(client, self.body_id, self.cfg.lasers, self.base.pose)
        self.microphones = SimMicrophones()
        self.tablet = SimTablet()

    def _index_links(self) -> tuple[dict[str, int], dict[str, int]]:
        """Link name -> index and revolute joint name -> index, from the loaded URDF."""
        links, joints = {}, {}
        for j in range(p.getNumJoints(self.body_id, physicsClientId=self.client)):
            info = p.getJointInfo(self.body_id, j, physicsClientId=self.client)
            links[info[12].decode()] = j
            if info[2] == p.JOINT_REVOLUTE:
                joints[info[1].decode()] = j
        return links, joints

    def link_index(self, name: str) -> int:
        """PyBullet link index of a link named in the URDF (e.g. "Head", "Tablet")."""
        if name not in self._links:
            raise ValueError(f"unknown link {name!r}; known: {sorted(self._links)}")
        return self._links[name]

    def step(self, dt: float) -> None:
        """Advance base motion, joint ramps, battery and motor temperature by ``dt``
        seconds. Call once per simulation step, before ``stepSimulation``."""
        if dt <= 0:
            raise ValueError(f"dt must be positive, got {dt}")
        driven, turned = self.base.advance(dt)
        self.joints.advance(dt)
        joint_speed = float(np.abs(self.joints.velocity).sum())
        self.battery.update(dt, driven / dt, turned / dt, joint_speed)
        self.thermal.update(dt, driven / dt, turned / dt, joint_speed, self.joints.resting)
