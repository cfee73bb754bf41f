"""The facing model: crops, angle classes, the rendered labels, a seeded small training
that resumes, and the shipped model against its bars on freshly rendered people."""

from __future__ import annotations

import math
import os
import signal

import numpy as np
import pytest
import torch
from test_training_resume import refuses_changes_and_bad_checkpoints

from app.cli import main
from perception.detector.training.data import SceneSpec
from perception.facing.config import DEFAULT_FACING_MODEL, CropConfig, load_facing_config
from perception.facing.model import (
    FacingEstimator,
    angle_bin,
    bin_centres,
    circular_mean,
    crop_person,
)
from perception.facing.training.data import (
    load_split,
    make_scene,
    spec_examples,
    write_facing_dataset,
)
from perception.facing.training.evaluate import bars_met, facing_metrics

CFG = load_facing_config()


def test_crop_letterboxes_the_padded_box():
    frame = np.zeros((240, 320, 3), np.uint8)
    frame[100:200, 50:80] = 255                       # a 30 x 100 white person
    crop = crop_person(frame, (50, 100, 79, 199), CropConfig(width=48, height=96), 0.0)
    assert crop.shape == (96, 48, 3)
    assert (crop[:, 24] == 255).all()                 # the person fills the height ...
    assert (crop[48, :5] == 114).all()                # ... with grey bars at the sides
    edge = crop_person(frame, (300, 0, 330, 50), CropConfig(width=48, height=96), 0.2)
    assert edge.shape == (96, 48, 3)                  # a box past the border still crops


def test_angle_classes_and_their_circular_mean():
    bins = 8
    assert list(angle_bin(np.radians([0, 44, 46, 180, -90, 359]), bins)) == [0, 1, 1, 4, 6, 0]
    for k in range(bins):
        probs = torch.zeros(bins)
        probs[k] = 1.0
        angle, strength = circular_mean(probs)
        assert math.isclose(math.remainder(float(angle) - float(bin_centres(bins)[k]),
                                           2 * math.pi), 0.0, abs_tol=1e-5)
        assert math.isclose(float(strength), 1.0, rel_tol=1e-5)


@pytest.fixture(scope="module")
def scene():
    s = make_scene(CFG.data)
    yield s
    s.close()


def test_a_person_looking_at_the_camera_has_angle_zero(scene):
    spec = scene.sample(np.random.SeedSequence([0, 0, 3]))
    person = spec.people[0]
    eye = scene.robot.camera.pose()[0]
    for turn, expected in ((0.0, 0.0), (math.pi / 2, math.pi / 2), (math.pi, math.pi)):
        facing = math.atan2(eye[1] - 0.0, eye[0] - 2.0) + turn
        one = SceneSpec(people=(type(person)(person.appearance, 2.0, 0.0, facing),),
                        head_pitch=0.1)
        rows = spec_examples(scene, one, CFG.data)
        assert len(rows) == 1
        assert abs(math.remainder(rows[0][1] - expected, 2 * math.pi)) < 1e-6


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    """A seeded small data set and a two-epoch training on it."""
    root = tmp_path_factory.mktemp("facing")
    config = root / "tiny.yaml"
    config.write_text("data: {splits: {train: 40, val: 8, test: 8}}\n"
                      "train: {epochs: 2, batch: 32, threads: 1}\n")
    assert main(["data", "facing", "--out", str(root / "data"), "--config", str(config)]) == 0
    assert main(["train", "facing", "--data", str(root / "data"), "--out", str(root / "run"),
                 "--config", str(config)]) == 0
    return root, config


def test_a_small_training_writes_a_loadable_model_and_resumes(tiny):
    root, config = tiny
    train = load_split(root / "data", "train")
    assert train["crops"].shape[1:] == (96, 48, 3) and len(train["angles"]) >= 40
    assert np.all(np.abs(train["angles"]) <= math.pi + 1e-6)
    log = (root / "run" / "train_log.csv").read_text().splitlines()
    assert len(log) == 3                                  # header and two epochs
    model = FacingEstimator.load(root / "run" / "facing.pt")
    assert 0.0 <= facing_metrics(model, load_split(root / "data", "test"))["mae_deg"] <= 180.0
    # run again into the same folder: refused without --resume, a no-op with it
    args = ["train", "facing", "--data", str(root / "data"), "--out", str(root / "run"),
            "--config", str(config)]
    assert main(args) == 2
    assert main([*args, "--resume"]) == 0
    assert len((root / "run" / "train_log.csv").read_text().splitlines()) == 3


def test_sigterm_stops_after_the_epoch_and_the_resume_matches_a_straight_run(
        tiny, tmp_path, monkeypatch, capsys):
    root, config = tiny
    real, calls = FacingEstimator.save, iter(range(1, 100))

    def save(self, path):  # SIGTERM while the first epoch's model is exported
        if next(calls) == 1:
            os.kill(os.getpid(), signal.SIGTERM)
        return real(self, path)

    args = ["train", "facing", "--data", str(root / "data"), "--out", str(tmp_path)]
    with monkeypatch.context() as m:
        m.setattr(FacingEstimator, "save", save)
        assert main([*args, "--config", str(config)]) == 143
    line = capsys.readouterr().err.strip().splitlines()[-1]
    assert "interrupted (SIGTERM), its checkpoint is kept" in line and line.endswith("--resume")
    assert len((tmp_path / "train_log.csv").read_text().splitlines()) == 2  # epoch 1 done
    assert main([*args, "--resume"]) == 0  # the run's own config
    cut, straight = ([r.rsplit(",", 1)[0] for r in (d / "train_log.csv").read_text().split()]
                     for d in (tmp_path, root / "run"))
    assert cut == straight  # every column but the wall time


def test_a_resume_keeps_the_run_config_and_refuses_an_unreadable_checkpoint(tiny, tmp_path,
                                                                           capsys):
    root, _ = tiny
    other = tmp_path / "other.yaml"
    other.write_text("data: {splits: {train: 40, val: 8, test: 8}}\n"
                     "train: {epochs: 3, batch: 32, threads: 1}\n")
    refuses_changes_and_bad_checkpoints(
        ["train", "facing", "--data", str(root / "data")], root / "run", tmp_path / "run",
        ["--config", str(other)], "train.epochs: run has 2, --config gives 3", capsys)


def test_the_data_set_is_seeded(tiny, tmp_path):
    root, config = tiny
    again = write_facing_dataset(tmp_path, load_facing_config(config).data)
    first, second = load_split(root / "data", "val"), load_split(tmp_path, "val")
    assert again["val"] == len(first["angles"])
    assert np.array_equal(first["crops"], second["crops"])


@pytest.mark.skipif(not DEFAULT_FACING_MODEL.is_file(), reason="no shipped facing model")
def test_shipped_model_meets_its_bars_on_fresh_people(tmp_path):
    """Rendered with a seed the shipped data set never used."""
    cfg = load_facing_config()
    recipe = cfg.data.model_copy(update={
        "seed": cfg.data.seed + 1000, "splits": cfg.data.splits.model_copy(
            update={"train": 0, "val": 0, "test": 150})})
    write_facing_dataset(tmp_path, recipe)
    shipped = FacingEstimator.load(DEFAULT_FACING_MODEL)
    result = facing_metrics(shipped, load_split(tmp_path, "test"))
    assert result["crops"] >= 150
    assert all(bars_met(result, cfg.eval.bars).values()), result


def test_eval_without_data_is_a_clear_error(tmp_path, capsys):
    assert main(["eval", "facing", "--data", str(tmp_path)]) == 2
    assert "companion data facing" in capsys.readouterr().err
