"""The head camera's rate follows need: the scenario's rate while someone is around, the idle
rate once no one has been seen or heard for a while, back at once when a voice is heard."""

from __future__ import annotations

import itertools
from pathlib import Path

import py_trees
import yaml

from app.wiring import make_context
from behaviours.blackboard import seed
from behaviours.config import load_behaviour_config
from behaviours.sense import Sense
from behaviours.skill import people_in_view
from behaviours.ticking import SimulationTree
from perception.detector.yolo import YoloDetector
from robot.percepts import HeardLine
from sim.scenario import load_scenario
from sim.simulation import Simulation

ROOT = Path(__file__).resolve().parents[1]


class FrameLog(py_trees.behaviour.Behaviour):
    """Records (time, a person box in the frame) for each new camera frame."""

    def __init__(self, ctx) -> None:
        super().__init__("FrameLog")
        self.ctx, self.frames, self.seen = ctx, [], 0

    def update(self) -> py_trees.common.Status:
        if self.ctx.frames_taken > self.seen:
            self.seen = self.ctx.frames_taken
            dets = py_trees.blackboard.Blackboard.storage["/detections"]
            self.frames.append((round(self.ctx.now, 1), bool(people_in_view(self.ctx, dets))))
        return py_trees.common.Status.SUCCESS


def sensing(tmp_path: Path, people: bool):
    """The living room (without its people unless ``people``): Sense and a frame log."""
    data = yaml.safe_load((ROOT / "worlds" / "living_room.yaml").read_text())
    if not people:
        data["people"] = []
    data.pop("personality", None)
    path = tmp_path / "room.yaml"
    path.write_text(yaml.safe_dump(data))
    sim = Simulation(load_scenario(path))
    ctx = make_context(sim, load_behaviour_config(), YoloDetector.from_config())
    seed(ctx, sim.scenario.robot.initial_drives(), action="stand_by")
    log = FrameLog(ctx)
    tree = SimulationTree(py_trees.composites.Sequence("sense", memory=False,
                                                       children=[Sense(ctx), log]), sim, ctx)
    tree.setup()
    return sim, ctx, tree, log


def test_an_empty_room_is_looked_at_less_often_until_a_voice_is_heard(tmp_path) -> None:
    sim, ctx, tree, log = sensing(tmp_path, people=False)
    cfg = ctx.config.perception
    assert ctx.camera_rate == 1.0 and cfg.idle_rate < ctx.camera_rate
    with sim:
        while sim.t < 30.0 - 1e-9:
            tree.tick()
        ctx.robot.tablet.touch(HeardLine(1, sim.t, "Anna", "Hello?", "robot", 0.0))
        while sim.t < 45.0 - 1e-9:
            tree.tick()
    times = [t for t, _ in log.frames]
    assert not any(person for _, person in log.frames)
    gaps = [(a, b - a) for a, b in itertools.pairwise(times)]   # (frame time, to the next)
    before_idle = [g for a, g in gaps if a < cfg.idle_after_s - 1]
    idle = [g for a, g in gaps if cfg.idle_after_s + 1 <= a < 29]
    heard = [g for a, g in gaps if 31 <= a < 30 + cfg.idle_after_s - 1]
    assert before_idle and all(abs(g - 1.0) < 0.05 for g in before_idle)
    assert idle and all(abs(g - 1 / cfg.idle_rate) < 0.05 for g in idle)
    assert heard and all(abs(g - 1.0) < 0.05 for g in heard)      # the voice woke it
    assert len(times) < 45 * 0.7                                 # fewer than at 1 Hz throughout


def test_a_person_in_view_keeps_the_scenario_rate(tmp_path) -> None:
    sim, ctx, tree, log = sensing(tmp_path, people=True)
    cfg = ctx.config.perception
    with sim:
        while sim.t < 40.0 - 1e-9:
            tree.tick()
    assert any(person for _, person in log.frames)
    last_seen = 0.0
    for (t, person), (t_next, _) in itertools.pairwise(log.frames):
        if person:
            last_seen = t
        expected = 1.0 if t - last_seen < cfg.idle_after_s else 1 / cfg.idle_rate
        assert abs(t_next - t - expected) < 0.05, (t, t_next, last_seen)
