"""Bad input files and folders given to `companion run`: each ends with exit 2 and one line
naming the file, never a traceback or a hang (docs/reliability.md)."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from app.cli import main

WORLD = Path(__file__).resolve().parents[1] / "worlds" / "living_room.yaml"


def _utf16(p: Path) -> None:
    p.write_text(WORLD.read_text(), encoding="utf-16")


def _latin1(p: Path) -> None:
    p.write_bytes(WORLD.read_bytes().replace(b"name: ", "name: Jos\xe9 ".encode("latin-1"), 1))


def _binary(p: Path) -> None:
    p.write_bytes(bytes(range(256)) * 4)


def _huge(p: Path) -> None:
    with p.open("w") as fh:
        fh.write(WORLD.read_text())
        fh.write("# padding\n" * 120_000)


def _directory(p: Path) -> None:
    p.mkdir()


def _empty(p: Path) -> None:
    p.write_text("")


SCENARIOS = [
    (_utf16, "a binary file (or UTF-16 text), expected UTF-8 text"),
    (_latin1, "not UTF-8 text"),
    (_binary, "a binary file"),
    (_huge, "larger than the 1,048,576-byte limit"),
    (_directory, "is a directory, not a file"),
    (_empty, "name: Field required"),
]


@pytest.mark.parametrize(("make", "message"), SCENARIOS, ids=[m.__name__ for m, _ in SCENARIOS])
def test_bad_scenario_files_exit_2_with_one_line(tmp_path, capsys, make, message):
    path = tmp_path / "scenario.yaml"
    make(path)
    assert main(["run", str(path), "--out", str(tmp_path / "run")]) == 2
    err = capsys.readouterr().err
    assert str(path) in err and message in err and "Traceback" not in err
    assert not (tmp_path / "run").exists()   # refused before the run folder is made


def test_a_personality_folder_is_named(tmp_path, capsys):
    scenario = tmp_path / "scenario.yaml"
    (tmp_path / "moods").mkdir()
    text = WORLD.read_text()
    assert "\npersonality: " in text
    scenario.write_text(re.sub(r"\npersonality: .*\n", "\npersonality: moods\n", text))
    assert main(["run", str(scenario), "--out", str(tmp_path / "run")]) == 2
    err = capsys.readouterr().err
    assert f"personality: not a file: {tmp_path / 'moods'}" in err and "Traceback" not in err


def test_a_fifo_as_scenario_is_refused_without_hanging(tmp_path):
    fifo = tmp_path / "scenario.yaml"
    os.mkfifo(fifo)
    done = subprocess.run([sys.executable, "-m", "app.cli", "run", str(fifo), "--out",
                           str(tmp_path / "run")], capture_output=True, text=True, timeout=120)
    assert done.returncode == 2
    assert "not a regular file (a pipe, socket or device)" in done.stderr
    assert "Traceback" not in done.stderr


@pytest.mark.parametrize("out", ["file/run", "/proc/companion-run"])
def test_an_unwritable_out_folder_is_named(tmp_path, capsys, out):
    (tmp_path / "file").write_text("not a folder")
    target = out if out.startswith("/") else str(tmp_path / out)
    assert main(["run", str(WORLD), "--duration", "1", "--out", target]) == 2
    err = capsys.readouterr().err
    assert f"{target}: cannot create the run folder" in err and "Traceback" not in err


def test_a_corrupt_facing_split_is_named(tmp_path, capsys):
    (tmp_path / "test.npz").write_bytes(b"PK\x03\x04 not really a zip")
    assert main(["eval", "facing", "--data", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert f"{tmp_path / 'test.npz'}: not a readable facing data split" in err
    assert "Traceback" not in err
