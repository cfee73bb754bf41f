"""The rooms speech is said in when the recogniser is adapted and evaluated: a living room
of a given size, quiet or with the TV on at the far wall, the robot near the other wall."""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from sim.acoustics import Acoustics, Point
from sim.layout import Room, RoomNoise
from sim.robot_config import load_robot_config

TV_DB = 60.0              # the TV one metre in front of it: a normal volume
ROBOT_FROM_WALL_M = 1.0   # the robot stands this far from the near wall, in the middle
NOISES = ("quiet", "tv")
ROBOT_HEADING = math.pi / 2   # the robot faces into the room, towards the TV's wall


def living_room(width: float, depth: float, noise: str, tv_db: float = TV_DB
                ) -> tuple[Acoustics, Point]:
    """The room's acoustics (the TV, when ``noise`` is ``tv``, at ``tv_db`` one metre in
    front of it) and where the robot stands in it."""
    source = RoomNoise(source="tv", source_db=tv_db) if noise == "tv" else RoomNoise()
    lounge = Room(name="lounge", x=(0.0, width), y=(0.0, depth), noise=source)
    tv = (width / 2, depth - 0.2)
    return (Acoustics(load_robot_config().acoustics, [lounge], [], {"tv": tv}),
            (width / 2, ROBOT_FROM_WALL_M))


def recording(acoustics: Acoustics, samples: np.ndarray, rate: int, speaker: Point,
              robot: Point, loops: Mapping[str, np.ndarray], rng: np.random.Generator,
              array: bool) -> np.ndarray:
    """What the robot standing at ``robot`` (facing :data:`ROBOT_HEADING`) records of
    ``samples`` said at ``speaker``: each of the head's microphones (``array``,
    ``(M, n)``) or one."""
    if array:
        return acoustics.at_array(samples, rate, speaker, robot, ROBOT_HEADING, loops, rng)
    return acoustics.at_microphones(samples, rate, speaker, robot, loops, rng)


def speaker_at(robot: Point, distance: float, rng: np.random.Generator) -> Point:
    """A place ``distance`` m in front of the robot, 40-140 degrees off the near wall."""
    angle = math.radians(rng.uniform(40, 140))
    return robot[0] + distance * math.cos(angle), robot[1] + distance * math.sin(angle)


def speaker_within(robot: Point, depth: float, distance_m: tuple[float, float],
                   rng: np.random.Generator) -> Point:
    """A place at a drawn distance in ``distance_m`` in front of the robot (the far end
    capped half a metre short of the far wall of a room ``depth`` deep)."""
    reach = min(distance_m[1], depth - robot[1] - 0.5)
    return speaker_at(robot, rng.uniform(distance_m[0], reach), rng)
