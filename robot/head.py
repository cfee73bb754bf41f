"""The head as a part of its own: where it points and where it is told to look, on the two
head joints of any :class:`~robot.body.Joints` (``HeadYaw``: left is positive;
``HeadPitch``: down is positive; rad, relative to the body).

Gaze is what the skills ask of the head (turn to a voice, look level at a seated person,
look around while standing by); gestures and postures, which move the head together with
the arms and hips, stay with the joints.
"""

from __future__ import annotations

from robot.body import Joints

YAW, PITCH = "HeadYaw", "HeadPitch"


class JointHead:
    """The :class:`~robot.body.Head` part on the head joints of ``joints``."""

    def __init__(self, joints: Joints) -> None:
        self.joints = joints

    def angles(self) -> tuple[float, float]:
        """The measured (yaw, pitch)."""
        at = self.joints.positions()
        return at[YAW], at[PITCH]

    def targets(self) -> tuple[float, float]:
        """Where the head is heading: (yaw, pitch)."""
        to = self.joints.targets()
        return to[YAW], to[PITCH]

    def yaw_limits(self) -> tuple[float, float]:
        """How far the head turns: (right-most, left-most) yaw."""
        return self.joints.limits()[YAW]

    def look(self, yaw: float | None = None, pitch: float | None = None,
             speed: float = 1.0) -> None:
        """Turn towards ``yaw`` and/or ``pitch`` (the other stays) at ``speed`` x the
        joints' speed limits."""
        targets = {name: angle for name, angle in ((YAW, yaw), (PITCH, pitch))
                   if angle is not None}
        self.joints.move(targets, speed)
