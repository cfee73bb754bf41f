"""The robot says the same name and likes every time, and remembers the person's name."""

from pathlib import Path

import pytest

from core.config_files import ConfigError
from dialogue.conversation import PersonaConfig, load_conversation_config
from dialogue.manager import DialogueContext, DialogueManager
from dialogue.persona import Persona, spoken_list
from dialogue.qa.bot import QABot


class EchoChat:
    def reply(self, text: str, context: DialogueContext) -> str:
        return f"echo: {text}"


@pytest.fixture
def manager(tmp_path: Path) -> DialogueManager:
    persona = Persona(PersonaConfig(name="Pip", kind="a companion robot",
                                    likes=["singing", "dancing", "photos"]))
    return DialogueManager(QABot.offline(out_dir=tmp_path), chitchat=EchoChat(),
                           persona=persona)


def test_name_and_likes_are_answered_the_same_every_time(manager: DialogueManager) -> None:
    names = {manager.respond(q).text for q in ("What's your name?", "who are you",
                                               "What should I call you?")}
    assert names == {"I'm Pip, a companion robot. What's your name?"}
    likes = {manager.respond(q).text for q in ("what do you like?", "What are your hobbies?")}
    assert likes == {"I like singing, dancing and photos."}
    assert manager.respond("what do you like?").route == "persona"
    assert manager.respond("I like tea").route == "chitchat"


def test_the_persons_name_is_remembered(manager: DialogueManager) -> None:
    assert manager.respond("Hi, I'm Anna.").text == "Nice to meet you, Anna!"
    assert manager.respond("what's my name?").text == "Your name is Anna."
    assert manager.respond("what's your name?").text.endswith("And you're Anna, aren't you?")
    for line in ("I'm Happy", "I'm tired", "I am fine thanks"):  # feelings, not names
        assert manager.respond(line).route == "chitchat"
    assert manager.context.name == "Anna"


def test_the_shipped_persona_is_valid(tmp_path: Path) -> None:
    persona = load_conversation_config().persona
    assert persona.name and persona.likes
    assert spoken_list(["a"]) == "a" and spoken_list(["a", "b", "c"]) == "a, b and c"
    bad = tmp_path / "conversation.yaml"
    bad.write_text("persona:\n  likes: []\n  colour: blue\n", encoding="utf-8")
    with pytest.raises(ConfigError, match="colour"):
        load_conversation_config(bad)
