"""``companion chat`` under a pseudo-terminal, its ``--json`` mode, and ``eval dialogue``."""

import io
import json
import os
import select
import subprocess
import sys
from pathlib import Path

import pytest

from app.cli import build_parser, main
from dialogue.cli import run_chat
from dialogue.factory import robot_mood

REPO = Path(__file__).resolve().parents[1]


class Terminal:
    """Read from a pty master until a marker shows up."""

    def __init__(self, fd: int) -> None:
        self.fd, self.buf = fd, ""

    def until(self, marker: str, timeout: float = 60.0) -> str:
        import time

        end = time.monotonic() + timeout
        while marker not in self.buf:
            left = end - time.monotonic()
            assert left > 0, f"no {marker!r} in {self.buf!r}"
            ready, _, _ = select.select([self.fd], [], [], left)
            if ready:
                try:
                    chunk = os.read(self.fd, 4096)
                except OSError:
                    chunk = b""
                assert chunk, f"terminal closed before {marker!r}: {self.buf!r}"
                self.buf += chunk.decode(errors="replace")
        seen, _, self.buf = self.buf.partition(marker)
        return seen


def test_repl_under_a_pseudo_terminal(tmp_path: Path) -> None:
    master, slave = os.openpty()
    proc = subprocess.Popen(
        [sys.executable, "-m", "app.cli", "chat", "--mood", "negative", "--out",
         str(tmp_path)], stdin=slave, stdout=slave, stderr=slave, cwd=REPO, close_fds=True)
    os.close(slave)
    term = Terminal(master)
    try:
        banner = term.until("you> ")
        assert "Robot mood: negative (forced by --mood)" in banner
        os.write(master, b"Can you play 'Happy Birthday' for Mia?\n")
        out = term.until("you> ")
        assert "robot [music]" in out and "action: sing_dance song=Happy Birthday" in out
        os.write(master, b"where is the teddy?\n")
        out = term.until("you> ")
        assert "robot [map]" in out and "tablet: " in out and ".png" in out
        os.write(master, b"\x01\x02 how are you? \x7f\n")
        assert "robot [companion]: Hello. How are you" in term.until("you> ")   # its own greeting
        os.write(master, b"/quit\n")
        assert proc.wait(timeout=30) == 0
    finally:
        if proc.poll() is None:
            proc.kill()
        os.close(master)


def test_json_mode_one_object_per_line(tmp_path: Path) -> None:
    args = build_parser().parse_args(["chat", "--json", "--out", str(tmp_path)])
    stdin = io.StringIO("What time is it in Sydney?\n\nWho was Mozart?\n" + "y" * 10_000 + "\n")
    stdout = io.StringIO()
    assert run_chat(args, stdin, stdout) == 0
    rows = [json.loads(line) for line in stdout.getvalue().splitlines()]
    assert [r["route"] for r in rows] == ["time", "empty", "information",
                                          "input_not_understood"]  # "yyyy..." is no word
    assert all(set(r) == {"input", "text", "route", "action", "tablet", "mood",
                                 "unstyled", "found", "act", "emotion", "care", "remembered"}
               for r in rows)
    assert [r["found"] for r in rows] == [True, False, True, False]
    assert rows[0]["mood"] == "positive" and rows[2]["tablet"].startswith("https://")


def test_piped_repl_commands(tmp_path: Path) -> None:
    args = build_parser().parse_args(["chat", "--out", str(tmp_path),
                                "--scenario", str(REPO / "worlds" / "birthday_party.yaml")])
    stdin = io.StringIO("/mode chitchat\nwhat time is it?\n/mode auto\n/mood negative\n"
                        "/context\nwhere is the cake?\n/bogus\n")
    stdout = io.StringIO()
    assert run_chat(args, stdin, stdout) == 0
    out = stdout.getvalue()
    assert "drives from the scenario" in out and "mode: chitchat" in out
    assert "robot [chitchat]" in out and "mood: negative" in out
    assert "The cake is on the cake table" in out and "/mode auto|qa|chitchat" in out


def test_mood_from_default_drives() -> None:
    mood, value, threshold = robot_mood()
    assert (mood, value, threshold) == ("positive", 0.0, 0.43)
    assert robot_mood({d: 1.0 for d in ("energy", "safety_rest", "belonging")})[0] == "negative"


def test_eval_dialogue_json(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["eval", "dialogue", "--json"]) == 0
    result = json.loads(capsys.readouterr().out)
    assert result["routing_accuracy"] >= 0.95 and result["n"] >= 200
    assert 0 < result["latency_ms_median"] < 1000


def test_user_errors_exit_2(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["chat", "--feed", str(tmp_path / "none.xml")]) == 2
    assert "none.xml: file not found" in capsys.readouterr().err
    bad = tmp_path / "weather.yaml"
    bad.write_text("cities: {Rome: {today: {temp_c: 3}}}\n")
    assert main(["chat", "--weather", str(bad)]) == 2
    assert "condition" in capsys.readouterr().err


def test_photo_is_a_real_head_camera_frame(tmp_path: Path) -> None:
    args = build_parser().parse_args(["chat", "--json", "--out", str(tmp_path)])
    stdout = io.StringIO()
    assert run_chat(args, io.StringIO("Please take a photo of us\n"), stdout) == 0
    row = json.loads(stdout.getvalue())
    assert row["route"] == "photo" and row["tablet"].endswith(".png")
    import cv2

    image = cv2.imread(row["tablet"])
    assert image.shape == (240, 320, 3) and image.std() > 10  # a rendered scene, not blank
    logged = json.loads((tmp_path / "dialogue.jsonl").read_text().splitlines()[-1])
    assert logged["tablet"] == row["tablet"] and logged["route"] == "photo"


def test_scenario_weather_answers_weather_questions(tmp_path: Path) -> None:
    args = build_parser().parse_args(["chat", "--json", "--out", str(tmp_path), "--scenario",
                                str(REPO / "worlds" / "low_battery_night.yaml")])
    stdout = io.StringIO()
    stdin = io.StringIO("How cold is it going to be in Berlin tomorrow?\n")
    assert run_chat(args, stdin, stdout) == 0
    row = json.loads(stdout.getvalue())
    assert row["route"] == "weather" and "-4" in row["text"]
