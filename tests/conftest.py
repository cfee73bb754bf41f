"""Fixtures shared by the find-people tests: the detector the robot loads and a
personality whose find_people ends soon after the greeting."""

from __future__ import annotations

from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
WEIGHTS = [w for w in (ROOT / "assets" / "models" / "detector.onnx",
                       ROOT / "assets" / "models" / "detector.pt",
                       ROOT / "runs" / "train-detector" / "weights" / "best.pt") if w.is_file()]


@pytest.fixture(scope="module")
def detector():
    """The first detector weights found (the tests that use it skip without any)."""
    from perception.detector.yolo import YoloDetector

    return YoloDetector(WEIGHTS[0])


@pytest.fixture
def short_relief(tmp_path):
    """A personality whose find_people lasts 2 steps, so a success ends soon after the greeting."""
    path = tmp_path / "personality.yaml"
    path.write_text("actions:\n  find_people: {duration: 2}\n")
    return path
