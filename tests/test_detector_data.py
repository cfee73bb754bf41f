"""The detector data set: boxes from the segmentation mask, the face rule, the CLI."""

from __future__ import annotations

import math
from dataclasses import astuple

import numpy as np
import pytest
import yaml

from app.cli import main
from core.config_files import ConfigError
from perception.detector.config import load_detector_config
from perception.detector.training.data import Box, DetectorScene, PersonSpec, SceneSpec, _extent
from sim.people import Appearance

CFG = load_detector_config().data


@pytest.fixture(scope="module")
def scene():
    s = DetectorScene(CFG)
    yield s
    s.close()


def test_boxes_match_mask_on_seeded_frame(scene):
    spec = scene.sample(np.random.SeedSequence([0, 0, 0]))
    assert spec.people
    frame = scene.render(spec)
    assert frame.boxes
    expected = set()
    for body, face in frame.people:
        mine = frame.bodies == body
        if mine.any():
            b = _extent(mine, 0)
            expected.add((0, b.x0, b.y0, b.x1, b.y1))
        face_mask = mine & np.isin(frame.links, face)
        if face_mask.any():
            b = _extent(face_mask, 1)
            expected.add((1, b.x0, b.y0, b.x1, b.y1))
    w, h = CFG.image.width, CFG.image.height
    labels = {astuple(Box.from_yolo(b.yolo(w, h), w, h)) for b in frame.boxes}
    assert labels <= expected  # every kept box is exactly a mask extent


def test_facing_away_has_person_but_no_face(scene):
    front = PersonSpec(Appearance(), 3.0, 0.0, math.pi)  # faces the robot
    back = PersonSpec(Appearance(), 3.0, 0.0, 0.0)
    assert sorted(b.cls for b in scene.render(SceneSpec(people=(front,))).boxes) == [0, 1]
    assert [b.cls for b in scene.render(SceneSpec(people=(back,))).boxes] == [0]


def test_empty_room_has_no_boxes(scene):
    assert scene.render(SceneSpec()).boxes == []


def test_cli_writes_tiny_dataset(tmp_path):
    out = tmp_path / "ds"
    args = ["data", "detector", "--out", str(out), "--train", "3", "--val", "1", "--test", "1",
            "--no-progress"]
    assert main(args) == 0
    for split, n in (("train", 3), ("val", 1), ("test", 1)):
        assert len(list((out / "images" / split).glob("*.png"))) == n
        assert len(list((out / "labels" / split).glob("*.txt"))) == n
    meta = yaml.safe_load((out / "data.yaml").read_text())
    assert meta["names"] == {0: "person", 1: "face"}
    assert meta["train"] == "images/train"
    assert len(list((out / "examples").glob("*.png"))) == 3
    assert not list(out.rglob(".*.tmp"))
    for label in (out / "labels").rglob("*.txt"):
        for line in label.read_text().splitlines():
            c, *box = line.split()
            assert c in ("0", "1") and all(0.0 <= float(v) <= 1.0 for v in box)
    assert main(args) == 0  # resuming renders nothing new


def test_bad_config_key_names_it(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("data:\n  min_box_pixels: 3\n")
    with pytest.raises(ConfigError, match=r"data\.min_box_pixels: unknown key"):
        load_detector_config(bad)
