"""Whether the one who just spoke looks away from the robot: the camera's cue for whom a
line is for, where the words name no one (docs/speech.md, *Who a line is for*).

People face whom they talk to. The chat skill turns the robot's head to a voice before it
answers; when the line's words called nobody, it looks at the person boxes of the first
frame that takes in every bearing within ``bearing_tolerance_deg`` of the voice's (as the
microphones localised it). One of the people seen there spoke, and the facing model
(perception/facing, run by Sense: ``facings``) read which way each looks: when every one
of them, confidently, looks more than ``away_deg`` away from the robot, the line was for
someone else, and the robot does not answer it. Only people within ``max_distance_m`` are
read: the facing model learnt people 0.8-5.5 m away (docs/facing.md), and a resident 8 m
away, facing the robot, was read as looking away. No one seen near the voice, anyone there
looking at the robot, or an unsure reading, and the words decide.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from behaviours.config import GazeConfig
from behaviours.person_range import PersonRange
from perception.detector.yolo import Detection
from perception.facing.model import Facing
from robot.geometry import wrap_angle


class SpeakerGaze:
    """Reads the speaker's facing in camera frames of the robot ``range`` belongs to."""

    def __init__(self, range_: PersonRange, cfg: GazeConfig) -> None:
        self.range, self.cfg = range_, cfg

    def covers(self, bearing: float, frame: np.ndarray) -> bool:
        """Whether ``frame`` takes in every bearing within the tolerance of ``bearing``
        (rad, world): else the speaker may stand beside it."""
        rows, cols = frame.shape[:2]
        tolerance = math.radians(self.cfg.bearing_tolerance_deg)
        left, right = (self._bearing(frame, col, rows / 2) for col in (0, cols))
        return (wrap_angle(left - bearing) >= tolerance
                and wrap_angle(bearing - right) >= tolerance)

    def near_voice(self, bearing: float, frame: np.ndarray,
                   people: list[Detection]) -> list[Detection]:
        """The person boxes whose world bearing lies within the tolerance of ``bearing``
        (rad): one of them spoke, if the speaker is in view."""
        tolerance = math.radians(self.cfg.bearing_tolerance_deg)
        return [box for box in people
                if abs(wrap_angle(self._bearing(frame, *box.centre) - bearing)) <= tolerance]

    def looks_away(self, bearing: float, frame: np.ndarray, depth: np.ndarray | None,
                   people: list[Detection],
                   facing: Callable[[Detection], Facing | None]) -> bool:
        """Whether everyone seen in ``frame`` (with its depth image ``depth`` and person
        boxes ``people``, whose ``facing`` Sense read) near the bearing of a voice and
        within ``max_distance_m``, at least one, looks away from the robot, confidently:
        whichever of them spoke did not speak to it."""
        readings = [facing(box) for box in self.near_voice(bearing, frame, people)
                    if self._within_reach(depth, box)]
        return bool(readings) and all(
            seen is not None and seen.confidence >= self.cfg.min_confidence
            and abs(math.degrees(seen.angle)) > self.cfg.away_deg for seen in readings)

    def _within_reach(self, depth: np.ndarray | None, box: Detection) -> bool:
        """Whether the person in ``box`` stands within ``max_distance_m`` (the facing
        model's data went no further; a person not measured in the depth image is not)."""
        reach = None if depth is None else self.range.distance(depth, box)
        return reach is not None and reach <= self.cfg.max_distance_m

    def _bearing(self, frame: np.ndarray, col: float, row: float) -> float:
        """The world bearing (rad) of the pixel (``col``, ``row``) of ``frame``."""
        _, ray = self.range.rays(frame.shape, np.asarray(col), np.asarray(row))
        return math.atan2(ray[1], ray[0])
