"""Bad input to `companion chat`, `companion ask` and `companion style`: a clear one-line
error and exit 2, or a documented result that says what was not done (exit 1), never a
traceback, a hang or a leftover temporary folder (docs/dialogue.md, docs/vqg.md,
docs/style_transfer.md)."""

from __future__ import annotations

import io
import os
import select
import signal
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

import cv2
import numpy as np
import pytest

from app.cli import main
from dialogue.style.files import StyleModelError

REPO = Path(__file__).resolve().parents[1]
GERMAN = "Das Essen war kalt und der Kellner war unfreundlich."


def companion(*argv: str, env: dict[str, str] | None = None, stdin: str = ""
              ) -> subprocess.CompletedProcess[str]:
    """The real command in a child process, so that a hang fails the test instead of it."""
    return subprocess.run([sys.executable, "-m", "app.cli", *argv], input=stdin, cwd=REPO,
                          capture_output=True, text=True, timeout=60,
                          env={**os.environ, **(env or {})})


def error_lines(stderr: str) -> list[str]:
    """Standard error without PyBullet's banner, which its import prints."""
    return [line for line in stderr.splitlines() if not line.startswith("pybullet build")]


def assert_one_line_error(status: int, err: str, *needles: str) -> None:
    assert status == 2 and "Traceback" not in err, err
    lines = error_lines(err)
    assert len(lines) == 1 and lines[0].startswith("companion: error: "), err
    assert all(n in lines[0] for n in needles), err


# --- the kinds of bad file ---------------------------------------------------------------

def _directory(p: Path) -> None:
    p.mkdir()


def _fifo(p: Path) -> None:
    os.mkfifo(p)


def _utf16(p: Path) -> None:
    p.write_text("the food was cold .\n", encoding="utf-16")


def _latin1(p: Path) -> None:
    p.write_bytes("the caf\xe9 was cold .\n".encode("latin-1"))


def _binary(p: Path) -> None:
    p.write_bytes(bytes(range(256)) * 4)


def _text(p: Path) -> None:
    p.write_text("not an image, not a feed\n")


def _empty(p: Path) -> None:
    p.write_bytes(b"")


def _missing(p: Path) -> None:
    pass


BadFile = tuple[Callable[[Path], None], str]
DIRECTORY: BadFile = (_directory, "is a directory, not a file")
FIFO: BadFile = (_fifo, "not a regular file (a pipe, socket or device)")
MISSING: BadFile = (_missing, "file not found")


def cases(*rows: tuple) -> list:
    """Parameters named by their kind of bad file (and the option, when the row has one)."""
    return [pytest.param(*row, id="-".join(v if isinstance(v, str) else v.__name__.strip("_")
                                          for v in row[:-1])) for row in rows]


# --- companion chat ----------------------------------------------------------------------

def left_in(tmp: Path) -> list[Path]:
    """What a session left in its temporary folder, but for onnxruntime's telemetry session
    file ``.ses``, which the library writes there when it is imported (the act model's
    encoder runs on it), whatever the session does."""
    return [p for p in tmp.iterdir() if p.name != ".ses"]


def test_chat_without_out_removes_its_temporary_folder(tmp_path):
    tmp = tmp_path / "tmp"
    tmp.mkdir()
    done = companion("chat", "--json", env={"TMPDIR": str(tmp)},
                     stdin="where is the teddy?\nPlease take a photo of us\n")
    assert done.returncode == 0 and "Traceback" not in done.stderr, done.stderr
    assert f"{tmp}/companion-chat-" in done.stdout and ".png" in done.stdout
    assert left_in(tmp) == []


def test_chat_removes_its_temporary_folder_on_sigterm(tmp_path):
    tmp = tmp_path / "tmp"
    tmp.mkdir()
    proc = subprocess.Popen([sys.executable, "-m", "app.cli", "chat"], cwd=REPO,
                            stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, env={**os.environ, "TMPDIR": str(tmp)})
    try:
        seen, end = b"", time.monotonic() + 60
        while b"you> " not in seen:
            assert time.monotonic() < end, seen
            if select.select([proc.stdout], [], [], 1)[0]:
                chunk = os.read(proc.stdout.fileno(), 4096)
                assert chunk, seen
                seen += chunk
        assert len(left_in(tmp)) == 1       # the session's folder, while it runs
        proc.send_signal(signal.SIGTERM)
        _, err = proc.communicate(timeout=30)
    finally:
        proc.kill()
    assert proc.returncode == 143 and b"Traceback" not in err, err
    assert left_in(tmp) == []


def test_chat_removes_its_temporary_folder_when_a_model_fails(tmp_path, monkeypatch, capsys):
    def broken() -> None:
        raise StyleModelError("style.pt: not a readable model file")

    monkeypatch.setattr("dialogue.factory.shipped_style", broken)
    monkeypatch.setattr("tempfile.tempdir", str(tmp_path))
    assert_one_line_error(main(["chat", "--json"]), capsys.readouterr().err,
                          "style.pt: not a readable model file")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(("option", "make", "message"), cases(
    ("--feed", *DIRECTORY), ("--feed", *MISSING), ("--feed", _binary, "not an RSS or Atom feed"),
    ("--feed", _text, "not an RSS or Atom feed"), ("--weather", *DIRECTORY),
    ("--scenario", _utf16, "a binary file (or UTF-16 text)"),
))
def test_chat_refuses_bad_files_by_name(tmp_path, monkeypatch, capsys, option, make, message):
    monkeypatch.setattr("tempfile.tempdir", str(tmp_path))
    path = tmp_path / "input.file"
    make(path)
    status = main(["chat", "--json", option, str(path)])
    err = capsys.readouterr().err
    assert status == 2 and f"{path}: " in err and message in err and "Traceback" not in err
    assert list(tmp_path.iterdir()) == ([path] if path.exists() else [])


def test_chat_refuses_a_fifo_as_feed_without_hanging(tmp_path):
    _fifo(tmp_path / "feed.xml")
    done = companion("chat", "--json", "--feed", str(tmp_path / "feed.xml"))
    assert_one_line_error(done.returncode, done.stderr, str(tmp_path / "feed.xml"), FIFO[1])


def test_chat_refuses_standard_input_that_is_not_utf8(monkeypatch, tmp_path, capsys):
    monkeypatch.setattr("sys.stdin", io.TextIOWrapper(io.BytesIO(b"caf\xe9\n"), "utf-8"))
    assert_one_line_error(main(["chat", "--json", "--out", str(tmp_path)]),
                          capsys.readouterr().err, "standard input: not UTF-8 text")


@pytest.mark.parametrize(("make", "message"), cases(DIRECTORY, (_binary, "a binary file")))
def test_eval_dialogue_refuses_bad_heldout_files(tmp_path, capsys, make, message):
    path = tmp_path / "heldout.tsv"
    make(path)
    assert_one_line_error(main(["eval", "dialogue", "--heldout", str(path)]),
                          capsys.readouterr().err, f"{path}: {message}")


# --- companion ask -----------------------------------------------------------------------

@pytest.fixture
def image(tmp_path) -> Path:
    path = tmp_path / "room.png"
    cv2.imwrite(str(path), np.random.default_rng(0).integers(0, 255, (240, 320, 3), np.uint8))
    return path


def test_ask_says_why_when_no_question_passes(tmp_path, image, capsys):
    strict = tmp_path / "strict.yaml"
    strict.write_text("decode:\n  min_logprob: 0.0\n")     # no question is that certain
    assert main(["ask", str(image), "-n", "3", "--config", str(strict)]) == 1
    out, err = capsys.readouterr()
    assert out == "" and "Traceback" not in err
    assert err.strip() == ("companion ask: no question passed the checks: of 12 decoded, 12 "
                           "fell below the confidence threshold (mean log-probability per "
                           "word 0.0); try another --seed or a larger -n")


def test_ask_prints_questions_and_exits_0(image, capsys):
    assert main(["ask", str(image), "-n", "2"]) == 0
    out, err = capsys.readouterr()
    assert 1 <= len(out.splitlines()) <= 2 and err == ""


@pytest.mark.parametrize(("make", "message"), cases(
    DIRECTORY, MISSING, (_text, "not an image OpenCV can decode"),
    (_empty, "not an image OpenCV can decode"),
))
def test_ask_refuses_what_is_no_image(tmp_path, capsys, make, message):
    path = tmp_path / "photo.png"
    make(path)
    assert_one_line_error(main(["ask", str(path)]), capsys.readouterr().err,
                          f"{path}: {message}")


def test_ask_refuses_a_fifo_without_hanging(tmp_path):
    _fifo(tmp_path / "photo.png")
    done = companion("ask", str(tmp_path / "photo.png"))
    assert_one_line_error(done.returncode, done.stderr, f"{tmp_path / 'photo.png'}: {FIFO[1]}")


# --- companion style ---------------------------------------------------------------------

@pytest.mark.parametrize(("argv", "stdin"), [
    ([""], ""), (["  ", ""], ""), ([], ""), ([], "\n \n\n"),
], ids=["empty-argument", "blank-arguments", "empty-stdin", "blank-stdin"])
def test_style_on_empty_input_says_there_is_nothing_to_transfer(monkeypatch, capsys, argv,
                                                                 stdin):
    monkeypatch.setattr("sys.stdin", io.StringIO(stdin))
    assert_one_line_error(main(["style", "--to", "positive", *argv]), capsys.readouterr().err,
                          "nothing to transfer: the input is empty")


@pytest.mark.parametrize(("text", "notice"), [
    (" ".join(["word"] * 2000), "line 1: printed unchanged: it has 2000 words, more than "
                                "the model's limit of 30"),
    (GERMAN, "line 1: printed unchanged: only 0% of its words are known to the model, fewer "
             "than 50% (is it English?)"),
], ids=["2000-words", "german"])
def test_style_says_what_it_did_not_translate(capsys, text, notice):
    assert main(["style", "--to", "positive", text]) == 1
    out, err = capsys.readouterr()
    assert out == text + "\n" and "Traceback" not in err
    assert err.splitlines() == [f"companion style: {notice}",
                                "companion style: 1 of 1 sentences printed unchanged"]


def test_style_translates_a_long_line_sentence_by_sentence(capsys):
    line = "the food was cold . " * 400                          # 2,000 words
    assert main(["style", "--to", "positive", line, GERMAN]) == 1
    out, err = capsys.readouterr()
    first, second = out.splitlines()
    assert len(first.split(". ")) == 400 and "cold" not in first and second == GERMAN
    assert err.splitlines()[-1] == "companion style: 1 of 401 sentences printed unchanged"


@pytest.mark.parametrize(("make", "message"), cases(
    (_utf16, "a binary file (or UTF-16 text), expected UTF-8 text"),
    (_binary, "a binary file (or UTF-16 text), expected UTF-8 text"),
    (_latin1, "not UTF-8 text (byte 7: b'\\xe9')"), DIRECTORY, MISSING,
))
def test_style_refuses_bad_input_files_by_name(tmp_path, capsys, make, message):
    path = tmp_path / "replies.txt"
    make(path)
    assert_one_line_error(main(["style", "--to", "positive", "--input", str(path)]),
                          capsys.readouterr().err, f"{path}: {message}")


def test_style_refuses_a_fifo_without_hanging(tmp_path):
    _fifo(tmp_path / "replies.txt")
    done = companion("style", "--to", "positive", "--input", str(tmp_path / "replies.txt"))
    assert_one_line_error(done.returncode, done.stderr,
                          f"{tmp_path / 'replies.txt'}: {FIFO[1]}")


@pytest.mark.parametrize("errors", ["strict", "surrogateescape"])
def test_style_refuses_standard_input_that_is_not_utf8(monkeypatch, capsys, errors):
    stdin = io.TextIOWrapper(io.BytesIO(b"the caf\xe9 was cold .\n"), "utf-8", errors=errors)
    monkeypatch.setattr("sys.stdin", stdin)
    assert_one_line_error(main(["style", "--to", "positive"]), capsys.readouterr().err,
                          "standard input: not UTF-8 text")
