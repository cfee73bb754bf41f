"""``companion chat --listen``: lines said by a household voice, padded with silence, read
from a WAV file in 30 ms blocks through the very loop the microphone feeds (the real
voice-activity detector, recogniser and dialogue), and the real failure where this computer
has no audio input."""

from __future__ import annotations

import io
import json
from pathlib import Path

import numpy as np
import pytest

from app.cli import main
from dialogue.cli import DEFAULT_SCENARIO, listen_and_answer
from dialogue.factory import chat_session
from dialogue.speech.listen import utterances, wav_blocks
from dialogue.speech.recognizer import SpeechRecognizer
from robot.voices import PEOPLE_VOICES, synthesise, wav_bytes

LINES = ("Please take a photo of us.", "What time is it in Paris?")


def write_lines(path: Path, lines: tuple[str, ...] = LINES) -> list[float]:
    """``lines`` said by the first household voice, 1 s of silence before, between and after,
    as a WAV file at the voice's own rate (22,050 Hz); where each line ends (s)."""
    parts, ends, at = [], [], 0
    for text in lines:
        samples, rate = synthesise(text, PEOPLE_VOICES[0])
        parts += [np.zeros(rate, np.int16), samples]
        at += rate + len(samples)
        ends.append(at / rate)
    parts.append(np.zeros(rate, np.int16))
    path.write_bytes(wav_bytes(np.concatenate(parts), rate))
    return ends


@pytest.fixture(scope="module")
def session(tmp_path_factory):
    """The dialogue of ``companion chat`` and the robot's recogniser, loaded once."""
    manager, _, _ = chat_session(None, DEFAULT_SCENARIO, None, None,
                                 tmp_path_factory.mktemp("chat"))
    return manager, SpeechRecognizer()


def test_each_line_heard_is_transcribed_and_answered_as_it_ends(tmp_path, session):
    manager, recognizer = session
    path = tmp_path / "two.wav"
    ends = write_lines(path)
    out = io.StringIO()
    assert listen_and_answer(wav_blocks(path), manager, "positive", out, as_json=True,
                             recognizer=recognizer) == 0
    replies = [json.loads(line) for line in out.getvalue().splitlines()]
    assert len(replies) == 2
    assert "photo" in replies[0]["heard"] and replies[0]["route"] == "photo"
    assert "paris" in replies[1]["heard"] and replies[1]["route"] == "time"
    for reply, end in zip(replies, ends, strict=True):
        assert abs(reply["end_s"] - end) <= 0.3 and reply["text"]


def test_an_utterance_is_given_before_the_rest_of_the_input_is_read(tmp_path):
    path = tmp_path / "two.wav"
    ends = write_lines(path)
    read = 0

    def counted():
        nonlocal read
        for block in wav_blocks(path):
            read += len(block)
            yield block

    starts = []
    seen = [read / 16_000 for _ in utterances(counted(), on_start=starts.append)]
    assert len(seen) == 2 and len(starts) == 2
    assert ends[0] + 0.4 < seen[0] < ends[0] + 0.8      # in the silence after the first line
    assert seen[1] < ends[1] + 0.8 < read / 16_000       # before the file's last second


def test_the_reply_is_printed_and_ctrl_c_leaves_with_status_0(tmp_path, session):
    manager, recognizer = session
    path = tmp_path / "one.wav"
    write_lines(path, LINES[:1])

    def then_ctrl_c():
        yield from wav_blocks(path)
        raise KeyboardInterrupt

    out = io.StringIO()
    assert listen_and_answer(then_ctrl_c(), manager, "positive", out,
                             recognizer=recognizer) == 0
    heard, reply = out.getvalue().splitlines()[:2]
    assert heard.startswith("heard: please take a photo of us")
    assert reply.startswith("robot [photo]: ")


def test_listen_without_an_input_device_is_a_one_line_error_with_status_2(capsys):
    sounddevice = pytest.importorskip("sounddevice")
    try:
        sounddevice.query_devices(kind="input")
        pytest.skip("this computer has an audio input")
    except sounddevice.PortAudioError:
        pass
    assert main(["chat", "--listen"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("companion: error: no audio input to listen to")
    assert len(err.strip().splitlines()) == 1


def test_listen_and_audio_cannot_be_asked_for_together(tmp_path):
    with pytest.raises(SystemExit) as exit_:
        main(["chat", "--listen", "--audio", str(tmp_path / "x.wav")])
    assert exit_.value.code == 2
