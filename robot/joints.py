"""The names of the robot's motorised joints (Pepper's), in the order the robot keeps them.

Kept apart from :mod:`sim.robot` so that files naming joints (the dance routines) can be
read without loading the simulator."""

JOINT_NAMES = (
    "HeadYaw", "HeadPitch",
    "LShoulderPitch", "LShoulderRoll", "LElbowYaw", "LElbowRoll", "LWristYaw",
    "RShoulderPitch", "RShoulderRoll", "RElbowYaw", "RElbowRoll", "RWristYaw",
    "HipRoll", "HipPitch", "KneePitch",
)
