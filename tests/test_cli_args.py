"""Out-of-range numbers on the command line are refused by name before any work starts."""

from __future__ import annotations

import pytest

from app.cli import main


@pytest.mark.parametrize(("argv", "message"), [
    (["run", "worlds/living_room.yaml", "--duration", "0"],
     "argument --duration: must lie between 0 and 604800"),
    (["run", "worlds/living_room.yaml", "--duration", "nan"],
     "argument --duration: must be a finite number, got nan"),
    (["run", "worlds/living_room.yaml", "--duration", "inf"],
     "argument --duration: must be a finite number, got inf"),
    (["run", "worlds/living_room.yaml", "--duration", "1e300"],
     "argument --duration: must lie between 0 and 604800"),
    (["run", "worlds/living_room.yaml", "--seed", "-1"],
     "argument --seed: must lie between 0 and 4294967295"),
    (["run", "worlds/living_room.yaml", "--seed", "1" * 23],
     "argument --seed: must lie between 0 and 4294967295"),
    (["eval", "policy", "--episodes", "0"], "argument --episodes: must lie between 1 and"),
    (["eval", "detector", "--iou", "1.5"], "argument --iou: must lie between 0 and 1, got 1.5"),
    (["eval", "detector", "--iou", "nan"], "argument --iou: must be a finite number"),
    (["export", "detector", "--imgsz", "0"], "argument --imgsz: must lie between 32 and 4096"),
    (["data", "detector", "--out", "x", "--train", "-3"], "argument --train: must lie between"),
    (["train", "detector", "--epochs", "0"], "argument --epochs: must lie between 1 and"),
    (["data", "vqg", "--out", "x", "--val", "-1"], "argument --val: must lie between 0 and"),
    (["eval", "vqg", "--samples", "0"], "argument --samples: must lie between 1 and"),
    (["ask", "image.png", "-n", "0"], "argument -n: must lie between 1 and 1000"),
    (["ask", "image.png", "-n", "100000"], "argument -n: must lie between 1 and 1000"),
    (["eval", "style", "--limit", "1"], "argument --limit: must lie between 2 and"),
    (["style", "--beam", "0"], "argument --beam: must lie between 1 and 64"),
    (["eval", "policy", "--episodes", "many"], "argument --episodes: invalid integer value"),
])
def test_out_of_range_numbers_are_refused_by_name(argv, message, capsys):
    with pytest.raises(SystemExit) as exit_info:
        main(argv)
    assert exit_info.value.code == 2
    assert message in capsys.readouterr().err
