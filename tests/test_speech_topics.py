"""The language model's topic questions: WordNet's most common nouns and people, each said
once in a frame, and nothing when WordNet is missing."""

from __future__ import annotations

import pytest

from app.cli import main
from core.config_files import ConfigError
from dialogue.conversation import load_conversation_config
from dialogue.speech.config import load_speech_config
from dialogue.speech.training.topics import general_english, topic_lines
from dialogue.speech.training.train import full_dictionary

WORDNET = load_conversation_config().knowledge.wordnet_dir


def small(nouns: int, people: int):
    return load_speech_config().train.topics.model_copy(update={"nouns": nouns,
                                                                "people": people})


def test_the_most_common_nouns_and_people_are_asked_about() -> None:
    cfg = small(200, 20)
    lines = topic_lines(cfg, WORDNET, set(full_dictionary()))
    assert len(lines) == 220
    starts = tuple(f.split("{}")[0] for f in cfg.noun_frames)
    assert all(" ".join(line).startswith(starts) for line in lines[:200])
    nouns = {w for line in lines[:200] for w in line} - {w for f in cfg.noun_frames
                                                          for w in f.split()}
    assert {"time", "man", "world"} & nouns            # everyday words are among the first
    logp = general_english()
    assert min(logp(w) for w in nouns) > logp("zymurgy")
    people = [" ".join(line) for line in lines[200:]]
    assert all(line.startswith(("who was", "who is", "tell me about")) for line in people)


def test_without_wordnet_there_are_no_topic_questions(tmp_path) -> None:
    cfg = small(10, 10)
    assert topic_lines(cfg, tmp_path, set(full_dictionary())) == []


def test_a_frame_without_a_slot_is_refused_with_exit_2(tmp_path, capsys) -> None:
    bad = tmp_path / "speech.yaml"
    bad.write_text("train: {topics: {noun_frames: ['what is it']}}\n")
    with pytest.raises(ConfigError, match=r"train\.topics: .*what is it"):
        load_speech_config(bad)
    assert main(["train", "asr", "--only", "language", "--config", str(bad),
                 "--out", str(tmp_path / "out")]) == 2
    assert "must hold one {} for the topic" in capsys.readouterr().err
    assert not (tmp_path / "out").exists()
