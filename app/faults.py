"""Fault injection for household runs: ``companion run ... --faults SPEC.yaml``.

A spec lists faults, each with its simulated start time ``at`` and, for lasting ones, a
duration ``for_s`` (docs/reliability.md has every kind and the recovery the robot must
show). :class:`FaultInjector` applies them to the simulation before each tick and logs a
``fault_injected`` event; the robot notices them only through its own senses and logs
what it does about it. :func:`fault_report` pairs each injected fault with the first event
of its recovery.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any, Literal

import numpy as np
from pydantic import Field, model_validator

from core.config_files import StrictModel, read_yaml, validate
from core.events import EventLog
from robot.joints import JOINT_NAMES
from sim.simulation import Simulation

Kind = Literal["camera_black", "camera_frozen", "detector_error", "detector_timeout",
               "dock_blocked", "person_vanishes", "joint_failure", "battery_drop",
               "speech_model_missing"]
# The events that show the robot's recovery from each kind (the first one after the fault).
RECOVERY: dict[str, tuple[str, ...]] = {
    "camera_black": ("fault",), "camera_frozen": ("fault",),
    "detector_error": ("fault",), "detector_timeout": ("fault",),
    "dock_blocked": ("dock_blocked", "dock_failed", "no_path"),
    "person_vanishes": ("find_failed", "person_found", "finished"),
    "joint_failure": ("fault", "posture_timeout"),
    "battery_drop": ("fault",),
    "speech_model_missing": ("fault",),
}
DETECTOR_TIMEOUT_S = 0.5   # how long a hung detector is waited for (wall time)


class Fault(StrictModel):
    """One fault: what, when (``at`` s), for how long (``for_s``; None: to the end)."""

    kind: Kind
    at: float = Field(default=0.0, ge=0)
    for_s: float | None = Field(default=None, gt=0)
    joint: str | None = None          # joint_failure: which joint
    level: float = Field(default=0.1, ge=0, le=1)   # battery_drop: the charge left

    @model_validator(mode="after")
    def _joint(self) -> Fault:
        if self.kind == "joint_failure" and self.joint not in JOINT_NAMES:
            raise ValueError(f"joint_failure needs `joint`, one of {', '.join(JOINT_NAMES)}")
        return self

    def lasts(self, since: float, t: float) -> bool:
        """Whether the fault, started at ``since``, still lasts at simulated time ``t``."""
        return since <= t and (self.for_s is None or t < since + self.for_s)


class FaultSpec(StrictModel):
    """A fault-injection file: ``faults: [...]``."""

    faults: tuple[Fault, ...] = Field(min_length=1)


def load_faults(path: str | Path) -> FaultSpec:
    """Load and validate a fault spec (errors name the file and the key)."""
    return validate(FaultSpec, read_yaml(path), str(path))


class FaultyDetector:
    """The detector, raising or hanging while a detector fault is active."""

    def __init__(self, detector: Any, injector: FaultInjector) -> None:
        self.detector, self.injector = detector, injector

    def __getattr__(self, name: str) -> Any:
        return getattr(self.detector, name)

    def detect(self, frame: np.ndarray, *args: Any, **kwargs: Any) -> Any:
        """The detections of ``frame``, or the active fault."""
        t = self.injector.sim.t
        if self.injector.active("detector_error", t):
            raise RuntimeError("injected fault: the detector failed")
        if self.injector.active("detector_timeout", t):
            time.sleep(DETECTOR_TIMEOUT_S)
            raise TimeoutError(f"injected fault: no detections within {DETECTOR_TIMEOUT_S} s")
        return self.detector.detect(frame, *args, **kwargs)


class FaultInjector:
    """Applies a :class:`FaultSpec` to ``sim`` as simulated time passes."""

    def __init__(self, spec: FaultSpec, sim: Simulation, events: EventLog) -> None:
        self.spec, self.sim, self.events = spec, sim, events
        self._started: dict[int, float] = {}   # fault index -> when it really started
        self._ended: set[int] = set()
        self._vanish_pending: list[int] = []

    def active(self, kind: str, t: float) -> bool:
        """Whether a fault of ``kind`` lasts at ``t``."""
        return any(self.spec.faults[i].kind == kind and self.spec.faults[i].lasts(since, t)
                   and i not in self._ended for i, since in self._started.items())

    def at_load(self, dialogue: Any) -> None:
        """Faults of the robot's start: the chit-chat model missing. The dialogue goes on
        without it (chit-chat lines get its "can't chat now" reply)."""
        for i, f in enumerate(self.spec.faults):
            if f.kind == "speech_model_missing":
                self._started[i] = 0.0
                self.events.emit("fault_injected", fault=f.kind)
                dialogue.chitchat = None
                self.events.emit("fault", fault=f.kind, error="the chit-chat model did not load",
                                 recovery="answer without chit-chat: QA as before, chit-chat "
                                 "lines get the dialogue's can't-chat reply")

    def apply(self, t: float, action: str | None) -> None:
        """Start and end the faults due at ``t``; ``action`` is the robot's running one
        (a person vanishes only while the robot is finding people; a box lands on the dock
        only while the robot is off it). A lasting fault lasts ``for_s`` from its start."""
        for i, f in enumerate(self.spec.faults):
            if i not in self._started and t >= f.at:
                if f.kind == "dock_blocked" and self.sim.robot.battery.charging:
                    continue   # a box can't land on the docked robot: wait until it leaves
                self._started[i] = t
                if f.kind == "person_vanishes":
                    self._vanish_pending.append(i)
                else:
                    self._start(f)
            elif i in self._started and i not in self._ended \
                    and not f.lasts(self._started[i], t):
                self._ended.add(i)
                self._end(f)
        if self._vanish_pending and action == "find_people":
            self._vanish(self.spec.faults[self._vanish_pending.pop(0)])

    def _start(self, f: Fault) -> None:
        robot, world = self.sim.robot, self.sim.world
        if f.kind in ("camera_black", "camera_frozen"):
            robot.camera.set_fault(f.kind.removeprefix("camera_"))
        elif f.kind == "joint_failure":
            robot.joints.fail(f.joint)  # type: ignore[arg-type]
        elif f.kind == "battery_drop":
            robot.battery.set_level(min(robot.battery.level, f.level))
        elif f.kind == "dock_blocked":
            dock = world.house.dock_pose()
            world.drop_box("fault_box", dock.x, dock.y)
        self.events.emit("fault_injected", fault=f.kind, **_details(f))

    def _end(self, f: Fault) -> None:
        robot, world = self.sim.robot, self.sim.world
        if f.kind in ("camera_black", "camera_frozen"):
            robot.camera.set_fault(None)
        elif f.kind == "joint_failure":
            robot.joints.fail(f.joint, failed=False)  # type: ignore[arg-type]
        elif f.kind == "dock_blocked":
            world.take_away("fault_box")
        self.events.emit("fault_cleared", fault=f.kind)

    def _vanish(self, f: Fault) -> None:
        """The person nearest the robot disappears."""
        people = self.sim.world.people_positions()
        if not people:
            return
        x, y, _ = self.sim.robot.base.pose()
        name = min(people, key=lambda n: np.hypot(people[n].x - x, people[n].y - y))
        self.sim.world.take_away(name)
        self.events.emit("fault_injected", fault=f.kind, person=name)


def _details(f: Fault) -> dict[str, Any]:
    out: dict[str, Any] = {"for_s": f.for_s}
    if f.kind == "joint_failure":
        out["joint"] = f.joint
    if f.kind == "battery_drop":
        out["level"] = f.level
    return out


def fault_report(events: Sequence[dict[str, Any]]) -> list[dict[str, Any]]:
    """Each injected fault with the first recovery event after it (None: not recovered)."""
    out = []
    for i, e in enumerate(events):
        if e["kind"] != "fault_injected":
            continue
        follow = next((f for f in events[i + 1:] if f["kind"] in RECOVERY[e["fault"]]
                       and (f["kind"] != "fault" or f.get("fault") == e["fault"])), None)
        out.append({"fault": e["fault"], "t": e["t"],
                    "recovery": None if follow is None else follow["kind"],
                    "recovery_t": None if follow is None else follow["t"]})
    return out

