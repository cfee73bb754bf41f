"""Whom a line is for is judged from its words: the vocative, found in transcripts that
have neither capitals nor commas."""

from __future__ import annotations

import pytest

from core.config_files import ConfigError
from dialogue.addressee import AddresseeJudge
from dialogue.conversation import load_conversation_config

HOUSEHOLD = ["Margaret", "Harold", "Nurse Lin", "Tom"]


@pytest.mark.parametrize(("text", "to"), [
    ("Margaret, shall we do the crossword after tea?", "margaret"),
    ("margaret shall we do the crossword after tea", "margaret"),   # as transcribed
    ("Cheer up, Harold. Fancy a game of chess?", "harold"),          # after an opener
    ("Oh Tom, would you put the kettle on?", "tom"),
    ("Nurse, could you help me up?", "nurse"),
    ("Dad, would you like a piece of cake?", "dad"),                  # a family title
    ("Hello everyone! Has everybody had their tea?", "everyone"),
    ("Pip, what time is it?", "robot"),                               # the robot's name
    ("How are you today, little robot?", "robot"),
    ("Is Margaret coming today?", "robot"),            # a name, but not calling anyone
    ("My son was supposed to visit today, but he cancelled.", "robot"),
    ("", "robot"),
])
def test_the_vocative_decides_whom_a_line_is_for(text: str, to: str) -> None:
    judged = AddresseeJudge("Pip", HOUSEHOLD).judge(text)
    assert judged.to == to
    assert judged.to_robot == (to in ("robot", "everyone"))


def test_a_line_that_calls_the_robot_last_still_names_it() -> None:
    """Only the first words are a vocative, but a line that calls the robot anywhere names
    it: the chat skill then leaves the camera's cue aside."""
    judge = AddresseeJudge("Pip", HOUSEHOLD)
    text = "you're doing a great job here robot keep it up"
    assert judge.judge(text).cue == "" and judge.names_robot(text)
    assert not judge.names_robot("is margaret coming today")


def test_the_robot_never_takes_its_own_name_for_someone_elses() -> None:
    judge = AddresseeJudge("Tom", HOUSEHOLD)       # a household member shares its name
    assert judge.judge("Tom, sing us a song").to == "robot"


@pytest.mark.parametrize("override", ["addressee: {first_words: 0}\n",
                                      "addressee: {openers: []}\n",
                                      "addressee: {typo: 1}\n"])
def test_bad_addressee_config_is_an_error(tmp_path, override: str) -> None:
    path = tmp_path / "conversation.yaml"
    path.write_text(override)
    with pytest.raises(ConfigError, match="addressee"):
        load_conversation_config(path)
