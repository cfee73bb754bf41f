"""What the behaviours of a household run share.

:class:`Household` holds the simulated robot and world, the services the skills call
(speech, detector, dialogue, question generator) and the run's clock and event log. The
tree's state lives on the py_trees blackboard under the keys of :data:`KEYS`, so that
``py_trees.display`` can show it and every behaviour declares what it reads and writes.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Protocol

import numpy as np

from app.core.events import EventLog
from app.mind.homeostasis import Homeostasis
from app.sim.navigation import PathFollower
from app.sim.robot import Robot
from app.sim.speech import Speaker
from app.sim.world import World
from behaviours.config import BehaviourConfig
from perception.detector.yolo import Detector


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
class Household:
    """The simulated household and the services a skill may use."""

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
    camera_rate: float = 2.0                 # frames per second while no one is tracked
    inbox: list[Any] = field(default_factory=list)    # social events not yet sensed
    frames_taken: int = 0                    # head-camera frames rendered so far
    snapshot: Any = None                     # callable(tag, frame) -> saved path, or None
    history: list[dict[str, Any]] = field(default_factory=list)  # one row per homeostasis step

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


# Blackboard keys (all at the root namespace) and what they hold.
KEYS = {
    "stimuli": "np.ndarray (3,): overheat, human_present, encouragement (0/1)",
    "drives": "np.ndarray (6,) in [0, 1]",
    "motivations": "np.ndarray (6,): eq. 3.4",
    "mood": "dict: value (eq. 3.6) and positive (bool)",
    "emotion": "float: the human's shown emotion, +1 happy, -1 sad, 0 none",
    "action": "str | None: the running action (app.mind.personality.ACTIONS)",
    "relieving": "bool: the running skill is satisfying its drive now",
    "progress": "int: homeostasis steps the running skill has been relieving",
    "act_status": "py_trees Status of the act subtree at the last tick",
    "frame": "np.ndarray | None: the latest head-camera frame (RGB)",
    "depth": "np.ndarray | None: its depth image (m along the optical axis, float32)",
    "frame_t": "float: when it was taken (simulated s)",
    "detections": "list[Detection] in the latest frame",
    "heard": "list[SayEvent]: what people said to the robot, not yet answered",
    "tracking": "float: camera rate (Hz) a skill steering by person boxes asks for; 0: none",
}


def make_household(sim: Any, config: BehaviourConfig | None = None,
                   detector: Detector | None = None, events_path: Any = None,
                   audio_dir: Any = None, **services: Any) -> Household:
    """A :class:`Household` around an :class:`app.sim.simulation.Simulation`: the scenario's
    personality, a clock that follows the simulation, an event log (in memory unless
    ``events_path``) and a speaker (WAVs into ``audio_dir`` when given). ``services``
    fills ``dialogue`` / ``questions``. The py_trees blackboard is cleared: build the
    household before its behaviours."""
    import py_trees

    from app.mind.personality import load_personality
    from behaviours.config import load_behaviour_config

    py_trees.blackboard.Blackboard.clear()
    scenario = sim.scenario
    clock = SimClock(sim.dt, sim.t)
    events = EventLog(events_path, clock)
    return Household(robot=sim.robot, world=sim.world,
                     homeostasis=Homeostasis(load_personality(scenario.personality)),
                     config=config or load_behaviour_config(), clock=clock, events=events,
                     speaker=Speaker(events, audio_dir), detector=detector,
                     camera_rate=scenario.camera_rate, **services)
