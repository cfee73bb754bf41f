"""What the behaviours of a tree share: their :class:`Context`.

The context holds the robot's body as named parts (``robot.body.Body``) and its map of the
household (``robot.navigation.FloorPlan``), the services the skills call (speech, detector,
dialogue, question generator) and the run's clock and event log; ``app/wiring.py`` makes
one around a simulation. The tree's
state lives on the py_trees blackboard instead (``behaviours/blackboard.py``).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Protocol

import numpy as np

from behaviours.config import BehaviourConfig
from behaviours.step_record import StepRecord
from core.events import EventLog
from mind.homeostasis import Homeostasis
from mind.preferences.config import AdaptationConfig, load_feedback_config
from mind.preferences.memory import Memory
from perception.detector.yolo import Detector
from perception.facing.model import FacingEstimator

if TYPE_CHECKING:
    from dialogue.manager import DialogueManager
    from dialogue.speech.recognizer import SpeechRecognizer
from robot.body import Body
from robot.navigation import FloorPlan
from robot.path_follower import PathFollower
from robot.percepts import SocialEvent
from robot.speaker import Speaker


class QuestionGenerator(Protocol):
    """Visual question generation (perception issue's VQG model)."""

    def ask(self, frame: np.ndarray, n: int) -> list[str]:
        """``n`` questions about the RGB frame, best first."""
        ...


@dataclass
class SimClock:
    """Simulated time (s) and the length of one simulation step."""

    dt: float
    t: float = 0.0

    def __call__(self) -> float:
        return self.t


@dataclass
class Context:
    """What every behaviour of a tree sees: the robot's body and its map, its homeostasis
    and services, the behaviour parameters, the clock and the event log (one per run;
    :func:`app.wiring.make_context` makes it from a simulation)."""

    robot: Body
    floor_plan: FloorPlan
    homeostasis: Homeostasis
    config: BehaviourConfig
    clock: SimClock
    events: EventLog
    speaker: Speaker
    detector: Detector | None = None
    dialogue: DialogueManager | None = None
    questions: QuestionGenerator | None = None
    facing: FacingEstimator | None = None    # which way a person in a box looks
    recognizer: SpeechRecognizer | None = None   # sounds -> words
    ask_again: Callable[[int, bool], None] = lambda line, closer: None  # "say that again"
                                             # (and "come closer") reaches people
    ask_way: Callable[[], None] = lambda: None   # "could someone clear the way" reaches them
    camera_rate: float = 2.0                 # frames per second while no one is tracked
    inbox: list[SocialEvent] = field(default_factory=list)   # the household's, not yet sensed
    frames_taken: int = 0                    # head-camera frames rendered so far
    snapshot: Callable[[str, np.ndarray], str | None] | None = None  # (tag, frame) -> saved
    steps: StepRecord = field(default_factory=StepRecord)  # the homeostasis steps so far
    contain_faults: bool = False   # an exception in a behaviour fails it (household runs)
    household: tuple[str, ...] = ()   # the names of the people it lives with (its set-up)
    memory: Memory | None = None   # the household's preferences: adapt to feedback when set
    memory_path: Path | None = None                 # where the memory is saved as it learns
    adaptation: AdaptationConfig = field(
        default_factory=lambda: load_feedback_config().adaptation)

    @property
    def now(self) -> float:
        """Simulated seconds since the run started."""
        return self.clock.t

    def path_follower(self) -> PathFollower:
        """A path follower with the ``pid`` gains, the robot's speed limits, the charge
        skill's waypoint tolerance and the simulated clock (docking and detours use it)."""
        base = self.robot.base.cfg
        return PathFollower(self.config.pid, base.max_linear_speed, base.max_angular_speed,
                            self.config.charge.waypoint_tolerance, self.clock)
