"""The ground truth of the robot's own camera frames in a household: what the frame shows
comes from the world (the segmentation mask), and a question is grounded only when
everything it mentions is in the frame."""

from __future__ import annotations

from pathlib import Path

import cv2
import pytest

from app.cli import main
from core.config_files import ConfigError
from perception.vqg.config import load_vqg_config
from perception.vqg.generator import DEFAULT_VQG_MODEL
from perception.vqg.training.data_config import load_vqg_data_config
from perception.vqg.training.dataset import VqgDataError
from perception.vqg.training.household import (
    evaluate_household,
    household_scene,
    judge_question,
    palette_name,
)
from sim.simulation import Simulation

WORLDS = Path(__file__).resolve().parents[1] / "worlds"
VISIBILITY = load_vqg_data_config().visibility


@pytest.fixture(scope="module")
def living_room():
    """The living room at the start: the robot faces Grace in the armchair."""
    with Simulation.from_file(WORLDS / "living_room.yaml") as sim:
        yield sim


def test_the_frame_shows_what_the_camera_sees(living_room):
    frame, scene = household_scene(living_room, VISIBILITY)
    assert frame.shape == (240, 320, 3)
    assert {n.kind for n in scene.nodes} == {"armchair", "person"}  # not the sofa behind
    grace = scene.people[0]
    assert grace.id == "Grace" and grace.pose == "sitting" and grace.pixels > 1000
    assert scene.room == "living_room" and scene.occasion == "quiet_afternoon"


@pytest.mark.parametrize(("question", "grounded"), [
    ("is there an armchair ?", True),
    ("how many people are there ?", True),
    ("is there a cake ?", False),
    ("what colour is the mug ?", False),   # the mug is on the coffee table, out of view
    ("what colour is the sofa ?", False),
])
def test_a_question_is_grounded_only_in_what_the_frame_holds(living_room, question, grounded):
    judged = judge_question(question, household_scene(living_room, VISIBILITY)[1])
    assert judged["parsed"] and judged["grounded"] is grounded


def test_colours_are_named_by_the_nearest_palette_colour():
    assert palette_name((0.9, 0.1, 0.1)) == "red"
    assert palette_name((0.5, 0.52, 0.56)) == "grey"


def test_an_unknown_occasion_is_a_clear_error(living_room):
    odd = Simulation(living_room.scenario.model_copy(update={"occasion": "wedding"}))
    with odd, pytest.raises(ConfigError, match="occasion"):
        household_scene(odd, VISIBILITY)


def test_eval_household_scores_the_frames_runs_saved(living_room, tmp_path):
    frame, scene = household_scene(living_room, VISIBILITY)
    frames = tmp_path / "run" / "frames"
    frames.mkdir(parents=True)
    cv2.imwrite(str(frames / "0001-t00000.1-chat.png"), cv2.cvtColor(frame, cv2.COLOR_RGB2BGR))
    (frames / "0001-t00000.1-chat.json").write_text(scene.to_json())
    cv2.imwrite(str(frames / "0002-t00001.0-photo.png"), frame)  # no truth beside: skipped
    cfg = load_vqg_config()
    result = evaluate_household(DEFAULT_VQG_MODEL, cfg, [tmp_path], samples=10)
    assert result["images"] == 1 and "bleu" not in result
    assert set(result["pass"]) == set(cfg.eval.household_bars)
    with pytest.raises(VqgDataError, match="no frames"):
        evaluate_household(DEFAULT_VQG_MODEL, cfg, [tmp_path / "empty"], samples=10)


def test_a_run_with_an_unknown_occasion_exits_2_before_it_starts(tmp_path, capsys):
    scenario = tmp_path / "odd.yaml"
    text = (WORLDS / "living_room.yaml").read_text()
    scenario.write_text(text.replace("name: living_room", "name: odd\noccasion: wedding", 1))
    assert main(["run", str(scenario), "--out", str(tmp_path / "run")]) == 2
    assert "occasion" in capsys.readouterr().err
    assert not (tmp_path / "run").exists()
