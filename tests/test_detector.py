"""The shipped person-and-face detector: finds people in seeded rendered frames, nobody in an
empty room, and reports bad weight files clearly."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from app.cli import main
from perception.detector.config import DEFAULT_DETECTOR, DEFAULT_TRAINED, load_detector_config
from perception.detector.training.data import DetectorScene, PersonSpec, SceneSpec
from perception.detector.training.train import onnx_input_shape
from perception.detector.yolo import DetectorFileError, YoloDetector
from sim.people import Appearance

CFG = load_detector_config()


@pytest.fixture(scope="module")
def scene():
    s = DetectorScene(CFG.data)
    yield s
    s.close()


@pytest.fixture(scope="module")
def detector():
    return YoloDetector.from_config(CFG.detect)


def _iou(a: tuple[float, ...], b: tuple[float, ...]) -> float:
    ix = max(0.0, min(a[2], b[2]) - max(a[0], b[0]))
    iy = max(0.0, min(a[3], b[3]) - max(a[1], b[1]))
    inter = ix * iy
    union = (a[2] - a[0]) * (a[3] - a[1]) + (b[2] - b[0]) * (b[3] - b[1]) - inter
    return inter / union if union > 0 else 0.0


def test_shipped_weights_exist():
    assert DEFAULT_DETECTOR.is_file()
    assert DEFAULT_DETECTOR.stat().st_size < 25 * 2**20


@pytest.mark.parametrize("distance,bearing_deg,pose", [
    (1.2, 0.0, "standing"), (2.5, 12.0, "standing"), (3.5, -15.0, "sitting"),
    (4.5, 5.0, "arms_raised")])
def test_finds_the_person(scene, detector, distance, bearing_deg, pose):
    b = math.radians(bearing_deg)
    person = PersonSpec(Appearance(), distance * math.cos(b), distance * math.sin(b),
                        math.pi + b, pose)
    frame = scene.render(SceneSpec(people=(person,)))
    truth = [bx for bx in frame.boxes if bx.cls == 0]
    assert len(truth) == 1
    t = truth[0]
    found = [d for d in detector.detect(frame.rgb) if d.cls == "person"]
    assert found, "no person detected"
    assert _iou(found[0].box, (t.x0, t.y0, t.x1 + 1, t.y1 + 1)) > 0.7


def test_face_seen_when_facing_the_camera(scene, detector):
    frame = scene.render(SceneSpec(people=(PersonSpec(Appearance(), 3.0, 0.0, math.pi),)))
    truth = [bx for bx in frame.boxes if bx.cls == 1]
    assert len(truth) == 1  # the face is in view at this distance
    faces = [d for d in detector.detect(frame.rgb) if d.cls == "face"]
    assert faces and faces[0].box[0] <= truth[0].x1 and faces[0].box[2] >= truth[0].x0


def test_empty_room_has_no_one(scene, detector):
    for seed in range(3):
        spec = scene.sample(np.random.SeedSequence([99, 3, seed]))
        frame = scene.render(SceneSpec(furniture=spec.furniture, wall=spec.wall,
                                       floor=spec.floor, light=spec.light))
        assert [d for d in detector.detect(frame.rgb) if d.conf >= 0.5] == []


def test_missing_weights_named(tmp_path):
    with pytest.raises(DetectorFileError, match="not found"):
        YoloDetector(tmp_path / "nope.pt")


def test_corrupt_weights_named(tmp_path):
    bad = tmp_path / "bad.pt"
    bad.write_bytes(b"\x00garbage" * 100)
    with pytest.raises(DetectorFileError, match=r"bad\.pt"):
        YoloDetector(bad)


def test_rejects_wrong_frame(detector):
    with pytest.raises(ValueError, match="uint8 RGB"):
        detector.detect(np.zeros((240, 320), np.uint8))


def test_corrupt_onnx_named(tmp_path):
    bad = tmp_path / "bad.onnx"
    bad.write_bytes(b"\x00garbage" * 100)
    with pytest.raises(DetectorFileError, match=r"bad\.onnx"):
        YoloDetector(bad)


def test_onnx_input_shape_fits_the_camera():
    assert onnx_input_shape(320, 320, 240) == (256, 320)
    assert onnx_input_shape(640, 320, 240) == (480, 640)


def test_shipped_onnx_matches_the_trained_weights(scene, detector):
    """The shipped ONNX file, run by our decoder, gives ultralytics' boxes for detector.pt."""
    trained = YoloDetector(DEFAULT_TRAINED)
    for seed in range(3):
        frame = scene.render(scene.sample(np.random.SeedSequence([7, 2, seed])))
        ours, theirs = detector.detect(frame.rgb), trained.detect(frame.rgb)
        assert [d.cls for d in ours] == [d.cls for d in theirs]
        for a, b in zip(ours, theirs, strict=True):
            assert abs(a.conf - b.conf) < 1e-3
            assert max(abs(x - y) for x, y in zip(a.box, b.box, strict=True)) < 0.05


def test_export_command_writes_the_robot_file(tmp_path):
    """`companion export detector` turns the shipped weights into an ONNX file the robot opens
    with the camera's letterboxed input."""
    out = tmp_path / "d.onnx"
    assert main(["export", "detector", "--out", str(out)]) == 0
    exported = YoloDetector(out)
    assert exported.model.shape == (256, 320) and exported.names == {0: "person", 1: "face"}


def test_export_names_a_bad_weights_file(tmp_path, capsys):
    bad = tmp_path / "bad.pt"
    bad.write_bytes(b"\x00garbage" * 100)
    for weights in (bad, tmp_path / "nope.pt"):
        assert main(["export", "detector", "--weights", str(weights),
                     "--out", str(tmp_path / "x.onnx")]) == 2
        assert weights.name in capsys.readouterr().err
    assert not (tmp_path / "x.onnx").exists()


@pytest.fixture(scope="module")
def test_frames(tmp_path_factory):
    """The first six frames of the rendered test split."""
    out = tmp_path_factory.mktemp("detector-data")
    assert main(["data", "detector", "--out", str(out), "--train", "0", "--val", "0",
                 "--test", "6", "--no-progress"]) == 0
    return out


def _eval_figures(data, capsys, *extra: str) -> dict:
    assert main(["eval", "detector", "--data", str(data), "--json", *extra]) == 0
    return json.loads(capsys.readouterr().out.splitlines()[-1])


def test_eval_scores_the_shipped_detector_at_the_robots_nms(test_frames, capsys):
    figures = _eval_figures(test_frames, capsys)
    assert figures["weights"].endswith("detector.onnx")
    assert figures["nms_iou"] == CFG.detect.iou
    # the model card's test-split bars, on a sample of that split
    assert figures["person_map50"] >= 0.95 and figures["person_map50_95"] >= 0.75
    assert figures["face_map50"] >= 0.90
    merged = _eval_figures(test_frames, capsys, "--iou", "0.01")
    assert merged["nms_iou"] == 0.01
    # an overlap that low merges neighbouring people: the boxes get worse, not better
    assert merged["person_map50_95"] < figures["person_map50_95"]
