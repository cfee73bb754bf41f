"""Wiring a household run: the behaviours' :class:`~behaviours.context.Context` around a
simulation, its simulated robot as the body and its world as the robot's map."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import py_trees

from behaviours.config import BehaviourConfig, load_behaviour_config
from behaviours.context import Context, SimClock
from core.events import EventLog
from mind.homeostasis import Homeostasis
from mind.personality import load_personality
from perception.detector.yolo import Detector
from robot.speaker import Speaker
from sim.simulation import Simulation


def make_context(sim: Simulation, config: BehaviourConfig | None = None,
                 detector: Detector | None = None, events_path: Path | None = None,
                 audio_dir: Path | None = None, **services: Any) -> Context:
    """A :class:`Context` around ``sim``: the scenario's personality, a clock that follows
    the simulation, an event log (in memory unless ``events_path``) and a speaker (WAVs
    into ``audio_dir`` when given). ``services`` fills ``dialogue`` / ``questions``. Only
    cheap objects are made here: the models are the caller's (``detector``, ``services``).
    The py_trees blackboard is cleared: make the context before the tree."""
    py_trees.blackboard.Blackboard.clear()
    scenario = sim.scenario
    clock = SimClock(sim.dt, sim.t)
    events = EventLog(events_path, clock)
    return Context(robot=sim.robot, floor_plan=sim.world.house,
                   homeostasis=Homeostasis(load_personality(scenario.personality)),
                   config=config or load_behaviour_config(), clock=clock, events=events,
                   speaker=Speaker(events, audio_dir, sim.robot.cfg.voice), detector=detector,
                   camera_rate=scenario.camera_rate, ask_again=sim.ask_again,
                   ask_way=sim.ask_way,
                   household=tuple(p.name for p in scenario.people), **services)
