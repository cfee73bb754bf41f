"""The robot's body as its software sees it: named parts, each a small sensor or controller.

In the way qiBullet composes a robot of sensor and controller objects, :class:`Body` is a
set of parts: the omnidirectional ``base``, the ``joints`` (head, arms and legs, with their
postures and gestures), the ``head``'s gaze, the forehead ``camera`` (colour with depth),
the base's ``lasers``, the ``battery``, the motors' ``thermal`` state, the head's
``microphones`` (the lines they recorded) and the chest ``tablet`` (what people typed or
pressed on it). The behaviours
drive the robot through these interfaces alone; ``sim/`` implements each of them on
PyBullet, and a real robot would implement them on its own drivers. Poses are
``(x, y, yaw)`` on the floor in the map's frame (m, m, rad).
"""

from __future__ import annotations

from typing import Protocol

import numpy as np
from pydantic import Field, NonNegativeFloat, PositiveFloat

from core.config_files import StrictModel
from robot.lasers import LasersConfig, Scan
from robot.percepts import FeedbackEvent, HeardLine, Sound

Pose = tuple[float, float, float]


class BaseConfig(StrictModel):
    """Base speed limits and the collision check."""

    max_linear_speed: PositiveFloat
    max_angular_speed: PositiveFloat
    collision_margin: NonNegativeFloat
    collision_step: PositiveFloat
    collision_turn_step: PositiveFloat


class CameraConfig(StrictModel):
    """Head camera intrinsics (vertical field of view, clip planes), and the share of each
    frame's rows a helper process renders when there is one (sim/split_render.py)."""

    fov_deg: float = Field(gt=0.0, lt=180.0)
    near: PositiveFloat
    far: PositiveFloat
    helper_share: float = Field(gt=0.0, lt=1.0)


class Base(Protocol):
    """The omnidirectional base: where it stands, and velocity commands that hold until
    changed (clamped to ``cfg``'s limits)."""

    cfg: BaseConfig

    def pose(self) -> Pose:
        """Where the base stands on the floor."""
        ...

    def set_velocity(self, vx: float, vy: float, wz: float) -> None:
        """Drive at (vx, vy) m/s in the robot's frame (x forward, y left), turning at wz."""
        ...

    def stop(self) -> None:
        """Stop the base."""
        ...

    @property
    def velocity(self) -> tuple[float, float, float]:
        """The (clamped) command in force."""
        ...

    @property
    def blocked(self) -> bool:
        """Whether an obstacle stopped (part of) the last step's motion."""
        ...


class Joints(Protocol):
    """The actuated joints by name, moved on ramps towards named postures or targets."""

    @property
    def names(self) -> tuple[str, ...]:
        """Every actuated joint, in a fixed order."""
        ...

    @property
    def posture(self) -> str | None:
        """The posture last asked for, or None once single joints were moved."""
        ...

    def limits(self) -> dict[str, tuple[float, float]]:
        """(lower, upper) angle of every joint (rad)."""
        ...

    def set_posture(self, name: str, speed: float | None = None) -> None:
        """Move every joint towards posture ``name`` at ``speed`` x the speed limits."""
        ...

    def move(self, targets: dict[str, float], speed: float) -> None:
        """Move the named joints towards ``targets`` (rad) at ``speed`` x the limits."""
        ...

    def positions(self) -> dict[str, float]:
        """The measured angle of every joint (rad)."""
        ...

    def targets(self) -> dict[str, float]:
        """Where every joint is heading (rad)."""
        ...

    def posture_reached(self) -> bool:
        """Whether the ramps have ended and every joint is within tolerance of its target."""
        ...

    def off_target(self) -> dict[str, float]:
        """The joints farther than the tolerance from their targets, with the error."""
        ...

    def tracking_errors(self) -> dict[str, float]:
        """|measured - commanded| per joint (rad): large where a joint cannot follow."""
        ...


class Head(Protocol):
    """The head's gaze (``HeadYaw`` left positive, ``HeadPitch`` down positive; rad,
    relative to the body): robot/head.py implements it on any body's joints."""

    def angles(self) -> tuple[float, float]:
        """The measured (yaw, pitch)."""
        ...

    def targets(self) -> tuple[float, float]:
        """Where the head is heading: (yaw, pitch)."""
        ...

    def yaw_limits(self) -> tuple[float, float]:
        """How far the head turns: (right-most, left-most) yaw."""
        ...

    def look(self, yaw: float | None = None, pitch: float | None = None,
             speed: float = 1.0) -> None:
        """Turn towards ``yaw`` and/or ``pitch`` (the other stays) at ``speed`` x the
        speed limits."""
        ...


class Camera(Protocol):
    """The forehead camera: colour frames with depth beside them, numbered."""

    cfg: CameraConfig

    @property
    def frame_seq(self) -> int:
        """The number of the last frame (a frozen camera repeats it)."""
        ...

    def frame(self, width: int = 320, height: int = 240) -> np.ndarray:
        """An RGB frame (height, width, 3) uint8."""
        ...

    def frame_with_depth(self, width: int = 320, height: int = 240,
                         ) -> tuple[np.ndarray, np.ndarray]:
        """An RGB frame and each pixel's distance along the optical axis (m)."""
        ...

    def pose(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Where the camera is, from the robot's kinematics: its position, optical axis
        (unit) and image-up vector in the map frame."""
        ...

    def heading(self) -> float:
        """Where the head faces on the floor (rad, map frame)."""
        ...

    def expression_at(self, u: float, v: float, width: int, height: int) -> str | None:
        """The expression (``happy``, ``sad``) on the face seen at pixel ``(u, v)`` of a
        ``width`` x ``height`` frame, or None (docs/what_the_robot_is_given.md)."""
        ...


class Lasers(Protocol):
    """The base's laser scanners."""

    cfg: LasersConfig

    @property
    def names(self) -> tuple[str, ...]:
        """The scanners, in the order of their rays."""
        ...

    def scan(self) -> Scan:
        """One reading of every ray, now."""
        ...


class Battery(Protocol):
    """The battery and the charger's contact."""

    @property
    def level(self) -> float:
        """State of charge in [0, 1]."""
        ...

    def set_level(self, level: float) -> None:
        """Set the state of charge (a household run keeps it at 1 - the energy drive)."""
        ...

    @property
    def charging(self) -> bool:
        """Whether the charger is plugged in."""
        ...

    def start_charging(self) -> None:
        """Plug the charger in (docked)."""
        ...

    def stop_charging(self) -> None:
        """Unplug the charger."""
        ...


class Thermal(Protocol):
    """The motors' temperature and the overheat alarm."""

    @property
    def temperature(self) -> float:
        """Lumped motor temperature (degrees C)."""
        ...

    @property
    def overheated(self) -> bool:
        """True from the overheat threshold until the motors cooled below the clear one."""
        ...


class Microphones(Protocol):
    """The head's microphones: the sound of each line in blocks, as it is said."""

    def recordings(self) -> list[Sound]:
        """The blocks of sound recorded since the last call, oldest first (each given once;
        a line's blocks in order, its last one marked ``ends``)."""
        ...


class Tablet(Protocol):
    """The chest tablet's touch screen: lines typed on it and thumbs pressed."""

    def inputs(self) -> list[HeardLine | FeedbackEvent]:
        """What people typed or pressed since the last call, oldest first (each once)."""
        ...


class Body(Protocol):
    """The robot as named parts."""

    base: Base
    joints: Joints
    head: Head
    camera: Camera
    lasers: Lasers
    battery: Battery
    thermal: Thermal
    microphones: Microphones
    tablet: Tablet
