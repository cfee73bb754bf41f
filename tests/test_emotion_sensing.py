"""An emotion counts only on a face the robot's camera finds: shown in front of it, the
mood's emotion term follows; shown behind its back, nothing is sensed."""

from __future__ import annotations

from pathlib import Path

import pytest

from app.run import build_run
from sim.layout import Placement
from sim.scenario import Event, Start, load_scenario

ROOT = Path(__file__).resolve().parents[1]


def tom_is_sad(robot_yaw: float):
    """The living room with Tom alone, standing 1.2 m east of the robot, looking sad from
    1 s on; the robot faces him (yaw 0) or away (180)."""
    base = load_scenario(ROOT / "worlds" / "living_room.yaml")
    tom = next(q for q in base.people if q.name == "Tom")
    tom = tom.model_copy(update={"start": Start(x=5.6, y=2.6, yaw=180.0),
                                 "events": (Event.model_validate({"at": 1.0,
                                                                  "emotion": "sad"}),)})
    robot = base.robot.model_copy(update={"start": Placement(x=4.4, y=2.6, yaw=robot_yaw)})
    return base.model_copy(update={"people": (tom,), "robot": robot, "duration": 8.0})


@pytest.mark.parametrize("robot_yaw, seen", [(0.0, True), (180.0, False)])
def test_an_emotion_counts_only_while_the_face_is_in_view(tmp_path, robot_yaw, seen):
    household = build_run(tom_is_sad(robot_yaw), tmp_path)
    with household.sim:
        for _ in range(80):
            household.tree.tick()
    emotions = [e for e in household.ctx.events.events if e["kind"] == "emotion"]
    assert bool(emotions) is seen
    assert all(e["emotion"] == "sad" for e in emotions)


def test_sense_puts_faces_and_facings_beside_the_detections(tmp_path):
    """The percepts of one frame: each confident face with its expression, and a facing
    for every person box (none for faces), aligned with ``detections``."""
    import py_trees

    household = build_run(tom_is_sad(0.0), tmp_path)
    with household.sim:
        for _ in range(30):
            household.tree.tick()
        storage = py_trees.blackboard.Blackboard.storage
        detections, facings, faces = (storage[f"/{k}"] for k in
                                      ("detections", "facings", "faces"))
    assert len(facings) == len(detections)
    people = [f for d, f in zip(detections, facings, strict=True) if d.cls == "person"]
    assert people and all(f is not None for f in people)
    assert all(f is None for d, f in zip(detections, facings, strict=True) if d.cls != "person")
    assert abs(people[0].angle) < 1.0   # Tom looks at the robot, which faces him
    assert faces and all(expression == "sad" for _, expression in faces)
