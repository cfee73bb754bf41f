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
