"""People's own voices (dialogue/speech/training/recordings.py): the human recordings of
Debian's pocketsphinx-testdata (make setup installs it) pair up with their reference texts,
Whisper makes out one of them, and a missing package is a user error naming make setup."""

from __future__ import annotations

import dataclasses

import jiwer
import pytest

from app.cli import main
from dialogue.speech.config import load_speech_config
from dialogue.speech.recognizer import SpeechRecognizer
from dialogue.speech.training import recordings
from dialogue.speech.training.recordings import (
    SETS,
    RecordingsError,
    available_sets,
    cards,
    goforward,
    librivox,
    sphinx_transcription,
)
from robot.audio import RATE


@pytest.mark.parametrize(("load", "listing", "transcription"), [
    (librivox, "librivox/fileids", "librivox/transcription"),
    (cards, "cards/cards.fileids", "cards/cards.transcription"),
])
def test_each_recording_has_its_own_transcription(load, listing, transcription):
    found = load()
    ids = (recordings.TESTDATA / listing).read_text().split()
    texts = sphinx_transcription(recordings.TESTDATA / transcription)
    assert [r.id for r in found] == ids and len(ids) == 5
    for r in found:
        assert r.path.is_file() and r.path.stem == r.id
        assert r.text == texts[r.id] and r.reference == " ".join(r.text.split())
        assert 0.5 < len(r.audio()) / RATE < 15


def test_goforward_is_the_sentence_of_its_grammar():
    (said,) = goforward()
    assert said.reference == "go forward ten meters"
    assert 2.5 < len(said.audio()) / RATE < 3.0      # 89,160 bytes of 16-bit samples


def test_whisper_makes_out_a_human_recording_straight_in():
    cfg = load_speech_config()
    cfg = cfg.model_copy(update={"model": cfg.model.model_copy(update={"engine": "whisper"})})
    (said,) = goforward()
    heard = SpeechRecognizer(cfg).transcribe(said.audio(), RATE)
    wrong = jiwer.process_words(said.reference, heard.text)
    assert wrong.substitutions + wrong.deletions + wrong.insertions <= 1, heard.text


def test_the_asterisk_prompts_pair_up_with_their_scripts():
    prompts, words = (s.load() for s in SETS if s.name.startswith("asterisk"))
    assert len(prompts) > 300 and len(words) > 150
    assert all(r.path.is_file() and r.reference for r in prompts + words)
    said = {r.id: r.reference for r in prompts + words}
    assert said["digits/7"] == "seven"
    assert said["vm-rec-name"] == ("after the tone say your name and then press the pound key")


def test_a_missing_package_is_a_user_error_naming_make_setup(monkeypatch, tmp_path, capsys):
    gone = dataclasses.replace(SETS[0], markers=(tmp_path / "fileids",))
    monkeypatch.setattr(recordings, "SETS", (gone, *SETS[1:]))
    with pytest.raises(RecordingsError, match="make setup"):
        available_sets()
    assert main(["eval", "asr", "--recordings", "--microphones", "one"]) == 2
    assert "pocketsphinx-testdata" in capsys.readouterr().err
