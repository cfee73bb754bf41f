"""Lines of symbols, far too long, in another script or of unknown words get a short honest
reply from the dialogue manager before chit-chat could guess; ordinary lines pass."""

from pathlib import Path

import pytest
import yaml

from dialogue.conversation import load_conversation_config
from dialogue.input_check import REPLIES, InputCheck
from dialogue.intent import HELDOUT_FILE, TRAIN_FILE, load_utterances
from dialogue.manager import DialogueContext, DialogueManager
from dialogue.qa.bot import QABot
from dialogue.qa.wordnet import WordNet

WORLDS = Path(__file__).resolve().parents[1] / "worlds"


class EchoChat:
    def reply(self, text: str, context: DialogueContext) -> str:
        return f"echo: {text}"


@pytest.fixture(scope="module")
def check() -> InputCheck:
    return InputCheck.default()


@pytest.mark.parametrize(("text", "reason"), [
    ("xxxxxxx", "not_understood"),
    ("asdf qwer", "not_understood"),
    ("Wie geht es dir heute?", "not_understood"),   # "es" is WordNet's "Es", not a word
    ("😀😀😀", "no_words"),
    ("!!! ???", "no_words"),
    ("\u4f60\u597d\uff0c\u4f60\u53eb\u4ec0\u4e48\u540d\u5b57\uff1f", "not_english"),  # Chinese
    ("Привет, как дела?", "not_english"),
    ("¿Dónde está la biblioteca?", "not_english"),   # Latin letters, unknown and accented
    ("word " * 61, "too_long"),
])
def test_unclear_lines(check: InputCheck, text: str, reason: str) -> None:
    unclear = check.check(text)
    assert unclear is not None and unclear.reason == reason
    assert unclear.text == REPLIES[reason] and unclear.route == f"input_{reason}"


@pytest.mark.parametrize("text", ["hello, how are you?", "I'm Anna", "Hmm", "42", "Hi Zandor",
                                  "who was einstein", "the cats were sleeping",
                                  "Look, I can still touch the sky! What's in the news today?"])
def test_ordinary_lines_pass(check: InputCheck, text: str) -> None:
    assert check.check(text) is None


def _said(node: object) -> list[str]:
    if isinstance(node, dict):
        return [v for k, v in node.items() if k == "say" and isinstance(v, str)] + [
            s for v in node.values() for s in _said(v)]
    return [s for v in node for s in _said(v)] if isinstance(node, list) else []


def test_every_shipped_line_passes(check: InputCheck) -> None:
    lines = [t for path in (TRAIN_FILE, HELDOUT_FILE) for _, t in load_utterances(path)]
    lines += [s for w in WORLDS.glob("*.yaml") for s in _said(yaml.safe_load(w.read_text()))]
    assert len(lines) > 800
    assert [t for t in lines if check.check(t)] == []


def test_without_wordnet_only_script_length_and_symbols_are_checked() -> None:
    check = InputCheck(load_conversation_config().input_check, None)
    assert check.check("asdf qwer") is None
    assert check.check("😀").reason == "no_words" and check.check("Привет").reason == "not_english"
    assert WordNet.load(Path("/nonexistent")) is None


def test_manager_answers_before_chitchat(tmp_path: Path) -> None:
    m = DialogueManager(QABot.offline(out_dir=tmp_path), chitchat=EchoChat())
    for text, route in [("xxxxxxx", "input_not_understood"), ("😀😀", "input_no_words"),
                        ("Привет", "input_not_english"), ("a " * 80, "input_too_long")]:
        reply = m.respond(text)
        assert reply.route == route and not reply.found
    assert m.respond("").route == "empty"
    assert m.respond("tell me a joke").text == "echo: tell me a joke"
