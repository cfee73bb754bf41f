"""Household frames of the VQG data set: the shipped worlds from the robot's own camera,
their ground truth from the segmentation mask, and resumable writing beside the scenes."""

from __future__ import annotations

import json

import numpy as np

from perception.vqg.questions import is_grounded, parse_question
from perception.vqg.training.data import write_vqg_dataset
from perception.vqg.training.data_config import load_vqg_data_config
from perception.vqg.training.frames_io import questions_for
from perception.vqg.training.household_data import run_frames

CFG = load_vqg_data_config()


def _cfg(**household):
    return CFG.model_copy(update={"household": CFG.household.model_copy(update=household)})


def test_close_ups_frame_a_person_from_the_front():
    cfg = _cfg(person_share=1.0, frames_per_moment=3)
    frames = list(run_frames(cfg, 3, np.random.SeedSequence([0, 10, 0]), 6))
    assert len(frames) == 6
    with_person = [g for _, g in frames if any(n.kind == "person" for n in g.nodes)]
    assert len(with_person) >= 5
    # a framed person fills a good part of the picture
    assert max(max(n.pixels for n in g.nodes if n.kind == "person") for g in with_person) > 3000


def test_room_frames_show_only_what_the_mask_holds():
    cfg = _cfg(person_share=0.0)
    for rgb, graph in run_frames(cfg, 1, np.random.SeedSequence([0, 10, 1]), 5):
        assert rgb.shape == (240, 320, 3)
        assert graph.room == "dining_room" and graph.occasion == "birthday_party"
        for node in graph.nodes:
            assert node.pixels >= getattr(cfg.visibility.min_pixels, node.category)
        for q in questions_for(graph, np.random.SeedSequence([1]), cfg):
            assert is_grounded(parse_question(q), graph), q


def test_household_frames_are_written_beside_the_scenes_and_resume(tmp_path):
    out = tmp_path / "vqg"
    cfg = _cfg(frames_per_run=2).model_copy(update={"examples": 1})
    done = write_vqg_dataset(out, cfg, {"train": 1}, progress=False, household={"train": 3})
    assert done == {"train": 4}
    ids = [json.loads(line)["id"] for line in
           (out / "questions" / "train.jsonl").read_text().splitlines()]
    assert ids == ["000000", "h000000", "h000001", "h000002"]
    (out / "images" / "train" / "h000002.png").unlink()
    again = write_vqg_dataset(out, cfg, {"train": 1}, progress=False, household={"train": 3})
    assert again == {"train": 1}
    assert (out / "examples" / "train_h000000.png").exists()
    assert json.loads((out / "meta.json").read_text())["household_counts"] == {"train": 3}
