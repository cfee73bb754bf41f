"""What the behaviours of a tree share: their :class:`Context`.

The context holds the simulated robot and world, the services the skills call (speech,
detector, dialogue, question generator) and the run's clock and event log. The tree's
state lives on the py_trees blackboard instead (``behaviours/blackboard.py``).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Protocol

import numpy as np
import py_trees

from behaviours.config import BehaviourConfig, load_behaviour_config
from behaviours.step_record import StepRecord
from core.events import EventLog
from mind.homeostasis import Homeostasis
from mind.personality import load_personality
from mind.preferences.config import AdaptationConfig, load_feedback_config
from mind.preferences.memory import Memory
from perception.detector.yolo import Detector
from perception.facing.model import FacingEstimator
from robot.path_follower import PathFollower
from robot.speaker import Speaker
from sim.robot import Robot
from sim.world import World


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
    """What every behaviour of a tree sees: the simulated robot and world, the robot's
    homeostasis and services, the behaviour parameters, the simulated clock and the event
    log (one per run; :func:`make_context` makes it from a simulation)."""

    robot: Robot
    world: World
    homeostasis: Homeostasis
    config: BehaviourConfig
    clock: SimClock
    events: EventLog
    speaker: Speaker
    detector: Detector | None = None
    dialogue: Any = None                     # dialogue.manager.DialogueManager
    questions: QuestionGenerator | None = None
    facing: FacingEstimator | None = None    # which way a person in a box looks
    recognizer: Any = None                   # dialogue.speech.SpeechRecognizer: sounds -> words
    ask_again: Callable[[int, bool], None] = lambda line, closer: None  # "say that again"
                                             # (and "come closer") reaches people
    ask_way: Callable[[], None] = lambda: None   # "could someone clear the way" reaches them
    camera_rate: float = 2.0                 # frames per second while no one is tracked
    inbox: list[Any] = field(default_factory=list)    # social events not yet sensed
    frames_taken: int = 0                    # head-camera frames rendered so far
    snapshot: Any = None                     # callable(tag, frame) -> saved path, or None
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
        base = self.robot.cfg.base
        return PathFollower(self.config.pid, base.max_linear_speed, base.max_angular_speed,
                            self.config.charge.waypoint_tolerance, self.clock)


def make_context(sim: Any, config: BehaviourConfig | None = None,
                 detector: Detector | None = None, events_path: Any = None,
                 audio_dir: Any = None, **services: Any) -> Context:
    """A :class:`Context` around an :class:`sim.simulation.Simulation`: the scenario's
    personality, a clock that follows the simulation, an event log (in memory unless
    ``events_path``) and a speaker (WAVs into ``audio_dir`` when given). ``services``
    fills ``dialogue`` / ``questions``. Only cheap objects are made here: the models are
    the caller's (``detector``, ``services``). The py_trees blackboard is cleared: make the
    context before the tree."""


    py_trees.blackboard.Blackboard.clear()
    scenario = sim.scenario
    clock = SimClock(sim.dt, sim.t)
    events = EventLog(events_path, clock)
    return Context(robot=sim.robot, world=sim.world,
                   homeostasis=Homeostasis(load_personality(scenario.personality)),
                   config=config or load_behaviour_config(), clock=clock, events=events,
                   speaker=Speaker(events, audio_dir, sim.robot.cfg.voice), detector=detector,
                   camera_rate=scenario.camera_rate, ask_again=sim.ask_again,
                   ask_way=sim.ask_way,
                   household=tuple(p.name for p in scenario.people), **services)
