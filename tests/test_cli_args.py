"""Out-of-range numbers on the command line are refused by name before any work starts."""

from __future__ import annotations

import pytest

from app.cli import main


@pytest.mark.parametrize(("argv", "message"), [
    (["run", "worlds/living_room.yaml", "--duration", "0"], "argument --duration: must be > 0"),
    (["run", "worlds/living_room.yaml", "--seed", "-1"], "argument --seed: must be >= 0"),
    (["eval", "policy", "--episodes", "0"], "argument --episodes: must be >= 1"),
    (["eval", "detector", "--iou", "1.5"], "argument --iou: must lie between 0 and 1, got 1.5"),
    (["eval", "detector", "--iou", "nan"], "argument --iou: must lie between 0 and 1"),
    (["export", "detector", "--imgsz", "0"], "argument --imgsz: must be >= 1, got 0"),
    (["data", "detector", "--out", "x", "--train", "-3"], "argument --train: must be >= 0"),
    (["train", "detector", "--epochs", "0"], "argument --epochs: must be >= 1"),
    (["data", "vqg", "--out", "x", "--val", "-1"], "argument --val: must be >= 0"),
    (["eval", "vqg", "--samples", "0"], "argument --samples: must be >= 1"),
    (["ask", "image.png", "-n", "0"], "argument -n: must be >= 1"),
    (["eval", "style", "--limit", "1"], "argument --limit: must be >= 2"),
    (["eval", "policy", "--episodes", "many"], "argument --episodes: invalid integer value"),
])
def test_out_of_range_numbers_are_refused_by_name(argv, message, capsys):
    with pytest.raises(SystemExit) as exit_info:
        main(argv)
    assert exit_info.value.code == 2
    assert message in capsys.readouterr().err
