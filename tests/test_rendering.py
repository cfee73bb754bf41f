"""The camera's split renderer: bands that make the whole frame, a helper process that
follows the world (people walking in, boxes dropped and taken away) and a run that goes on
when the helper dies."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pybullet as p
import pytest
import yaml

from sim.render import band_projection, tiny_render
from sim.scenario import load_scenario
from sim.simulation import Simulation
from sim.split_render import SplitRenderer

ROOT = Path(__file__).resolve().parents[1]
MAX_EDGE_PIXELS = 40   # of 76,800: where two surfaces are equally near, either may win


def busy_living_room(tmp_path: Path):
    """The living room with Tom coming in at 1 s, walking about and leaving at 7 s."""
    data = yaml.safe_load((ROOT / "worlds" / "living_room.yaml").read_text())
    data.pop("personality", None)
    for person in data["people"]:
        person["events"] = [e for e in person.get("events", []) if e["at"] < 20]
    tom = next(person for person in data["people"] if person["name"] == "Tom")
    tom["events"] = [{"at": 1, "enter": {"door": "hall_door"}},
                     {"at": 1.5, "walk_to": {"x": 2.0, "y": 2.4, "speed": 0.9}},
                     {"at": 7, "leave": True}]
    path = tmp_path / "busy.yaml"
    path.write_text(yaml.safe_dump(data))
    return load_scenario(path)


def differing(a: np.ndarray, b: np.ndarray) -> int:
    return int((np.abs(a.astype(int) - b).max(axis=2) > 0).sum())


def test_two_bands_make_the_whole_frame(tmp_path) -> None:
    with Simulation(busy_living_room(tmp_path)) as sim:
        robot = sim.robot
        for yaw in np.linspace(0, 2 * np.pi, 6, endpoint=False):
            x, y, _ = robot.base.pose()
            robot.base.set_pose(x, y, yaw)
            whole = robot.camera.frame()
            view, proj = robot.camera.matrices(320, 240)
            bands = [tiny_render(sim.client, 320, r1 - r0, view, band_projection(proj, 240, r0, r1),
                                 p.ER_NO_SEGMENTATION_MASK,
                                 sim.world.light.camera_kwargs())[0][..., :3]
                     for r0, r1 in ((0, 100), (100, 240))]
            assert differing(np.concatenate(bands), whole) <= MAX_EDGE_PIXELS


def test_the_helper_follows_people_and_boxes_and_draws_what_one_process_draws(tmp_path) -> None:
    scenario = busy_living_room(tmp_path)
    with Simulation(scenario) as one, Simulation(scenario, camera_helper=True) as split:
        assert isinstance(split.robot.camera.renderer, SplitRenderer)
        x, y, _ = one.robot.base.pose()
        tom_seen = False
        for step in range(100):
            for sim in (one, split):
                sim.step()
                if step == 30:
                    sim.world.drop_box("box", x + 1.2, y)
                if step == 60:
                    sim.world.take_away("box")
            if step % 5 == 0:
                for sim in (one, split):     # turn to face Tom's walk, then the room
                    sim.robot.base.set_pose(x, y, 0.35 * step / 5)
                a, da = one.robot.camera.frame_with_depth()
                b, db = split.robot.camera.frame_with_depth()
                assert split.robot.camera.renderer.alive
                assert differing(a, b) <= MAX_EDGE_PIXELS, step
                assert np.abs(da - db).max() < 0.01
                tom_seen |= "Tom" in one.world.people
        _, seg = one.robot.camera.frame_with_segmentation()
        _, seg2 = split.robot.camera.frame_with_segmentation()
        assert (seg != seg2).sum() <= MAX_EDGE_PIXELS        # the same body ids
        assert tom_seen and [e[0] for e in split.world.journal] == ["make", "make", "remove"]


@pytest.mark.parametrize("how", ["kill", "out_of_step"])
def test_a_failed_helper_is_dropped_and_frames_go_on(tmp_path, how, caplog) -> None:
    scenario = busy_living_room(tmp_path)
    with Simulation(scenario) as one, Simulation(scenario, camera_helper=True) as split:
        renderer = split.robot.camera.renderer
        split.robot.camera.frame()
        if how == "kill":
            renderer._proc.kill()
            renderer._proc.join()
        else:   # a body the helper never heard of takes the id it expects next
            split.world.journal.append(("make", 999, "ghost", "<link name='base'/>"))
        frame = split.robot.camera.frame()
        assert not renderer.alive
        assert "camera helper dropped" in caplog.text
        assert differing(frame, one.robot.camera.frame()) == 0


def test_a_frame_with_shadows_is_drawn_whole_in_the_run(tmp_path) -> None:
    scenario = busy_living_room(tmp_path)
    scenario = scenario.model_copy(update={"lighting": scenario.lighting.model_copy(
        update={"shadows": True})})
    with Simulation(scenario) as one, Simulation(scenario, camera_helper=True) as split:
        assert split.world.light.shadows
        assert differing(one.robot.camera.frame(), split.robot.camera.frame()) == 0
