"""Faults inside the robot never end a household run: each injected fault is noticed by the
robot's own senses and followed by its recovery event (docs/reliability.md)."""

from __future__ import annotations

import json
from types import SimpleNamespace

import py_trees
import pytest
from py_trees.common import Status

from app.cli import main
from app.faults import RECOVERY
from behaviours.skill import ContextBehaviour
from core.events import EventLog

SHORT = """faults:
  - {kind: speech_model_missing}
  - {kind: camera_black, at: 5, for_s: 5}
  - {kind: camera_frozen, at: 12, for_s: 5}
  - {kind: detector_error, at: 20, for_s: 5}
  - {kind: detector_timeout, at: 27, for_s: 1}
  - {kind: joint_failure, at: 30, for_s: 10, joint: HeadPitch}
  - {kind: dock_blocked, at: 45}
  - {kind: battery_drop, at: 50, level: 0.1}
"""


def test_every_injected_fault_is_followed_by_its_recovery(tmp_path, capsys):
    spec = tmp_path / "faults.yaml"
    spec.write_text(SHORT)
    out = tmp_path / "run"
    assert main(["run", "worlds/living_room.yaml", "--duration", "90", "--faults", str(spec),
                 "--out", str(out), "--no-progress", "--json"]) == 0
    metrics = json.loads(capsys.readouterr().out.splitlines()[-1])
    report = {f["fault"]: f for f in metrics["faults"]}
    assert set(report) == set(RECOVERY) - {"person_vanishes"}
    assert all(f["recovery"] is not None and f["recovery_t"] - f["t"] < 20
               for f in report.values()), report
    assert report["dock_blocked"]["recovery"] == "dock_blocked"
    events = [json.loads(line) for line in (out / "events.jsonl").read_text().splitlines()]
    recovered = {e["fault"] for e in events if e["kind"] == "recovered"}
    assert {"camera_black", "camera_frozen", "detector_error", "detector_timeout",
            "joint_failure"} <= recovered
    assert not [e for e in events if e.get("fault") == "behaviour_error"]
    said = [e["text"] for e in events if e["kind"] == "say"]
    assert "Something is in the way of my dock. Could someone clear it, please?" in said


@pytest.mark.parametrize(("text", "message"), [
    ("faults: [{kind: joint_failure, at: 3}]", "faults[0]: Value error, joint_failure needs"),
    ("faults: [{kind: meteor, at: 3}]", "faults[0].kind: Input should be"),
    ("faults: [{kind: camera_black, at: .nan}]", "faults[0].at: Input should be a finite"),
    ("faults: []", "faults: Tuple should have at least 1 item"),
])
def test_bad_fault_specs_exit_2_naming_the_key(tmp_path, capsys, text, message):
    spec = tmp_path / "faults.yaml"
    spec.write_text(text)
    assert main(["run", "worlds/living_room.yaml", "--faults", str(spec), "--out",
                 str(tmp_path / "run")]) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err


class Broken(ContextBehaviour):
    def update(self) -> Status:
        raise ZeroDivisionError("a bug in a skill")


def test_a_behaviour_that_raises_fails_with_a_fault_event_when_faults_are_contained():
    events = EventLog(None, lambda: 1.5)
    for contain in (True, False):
        ctx = SimpleNamespace(events=events, contain_faults=contain)
        root = py_trees.composites.Selector("root", memory=False, children=[
            Broken("Broken", ctx), py_trees.behaviours.Success("Fallback")])
        tree = py_trees.trees.BehaviourTree(root)
        if contain:
            tree.tick()
            assert root.children[0].status == Status.FAILURE and root.status == Status.SUCCESS
            fault = events.of_kind("fault")[0]
            assert fault["behaviour"] == "Broken"
            assert fault["error"] == "ZeroDivisionError: a bug in a skill"
        else:   # tests and tools see the bug itself
            with pytest.raises(ZeroDivisionError):
                tree.tick()
