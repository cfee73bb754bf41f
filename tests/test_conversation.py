"""A companion worth talking to: what people share is read (act, care signal, topic), and
answered in their feeling and their own terms, with care alerts, a topic kept over a few
turns and no reply said twice. The shipped act model and the shipped chit-chat and style
models answer, as in a household run."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from core.config_files import ConfigError
from dialogue.acts.config import load_acts_config
from dialogue.acts.model import load_act_lines
from dialogue.acts.replies import CompanionTalk
from dialogue.acts.topics import reflect
from dialogue.conversation_eval import HELDOUT_FILE, contradiction, load_heldout
from dialogue.factory import shipped_chitchat, shipped_style
from dialogue.manager import DialogueContext, DialogueManager
from dialogue.qa.bot import QABot
from dialogue.style.mood_config import load_mood_config
from mind.preferences.memory import load_memory, save_memory

DATA = Path(__file__).resolve().parents[1] / "dialogue" / "data"


@pytest.fixture(scope="module")
def talk() -> CompanionTalk:
    return CompanionTalk.load(staff=True)


@pytest.fixture(scope="module")
def manager(talk: CompanionTalk, tmp_path_factory) -> DialogueManager:
    qa = QABot.offline(out_dir=tmp_path_factory.mktemp("qa"))
    return DialogueManager(qa, chitchat=shipped_chitchat(), style=shipped_style(), talk=talk)


def test_the_three_line_sets_are_apart() -> None:
    """Training, development and test lines were written separately: none is in two."""
    train = {t.lower() for _, _, t in load_act_lines(DATA / "acts_train.tsv")}
    dev = {li.text.lower() for li in load_heldout(DATA / "conversation_dev.tsv")}
    test = {li.text.lower() for li in load_heldout(HELDOUT_FILE)}
    assert len(test) >= 200 and not (train & test) and not (dev & test) and not (train & dev)


@pytest.mark.parametrize(("line", "act", "care"), [
    ("my cat died last month", "loss", None),
    ("my knee hurts a lot today", "unwell", "pain"),
    ("i feel dizzy when i stand up", "unwell", "dizzy"),
    ("i'm scared of falling", "worry", "fall"),
    ("My daughter Susan is coming on Sunday", "plan", None),
    ("what's the weather like tomorrow", "question", None),
])
def test_the_act_and_care_signal_of_everyday_lines(talk: CompanionTalk, line: str, act: str,
                                                   care: str | None) -> None:
    reading = talk.read(line)
    assert reading.act == act and talk.model.alert(reading) == care


@pytest.mark.parametrize("mood", ["positive", "negative"])
def test_sad_news_gets_no_cheer_and_good_news_no_sorrow(manager: DialogueManager,
                                                        mood: str) -> None:
    moods = load_mood_config()
    sad = manager.respond("i feel so lonely since my wife passed away", mood, DialogueContext())
    assert sad.route == "companion" and sad.emotion == "negative"
    assert contradiction(sad.text, "negative", moods) is None and "wife" in sad.text
    happy = manager.respond("my granddaughter had a baby boy last night", mood,
                            DialogueContext())
    assert happy.emotion == "positive" and contradiction(happy.text, "positive", moods) is None
    assert "granddaughter" in happy.text


def test_a_care_signal_gets_a_calm_reply_that_brings_in_help(manager: DialogueManager) -> None:
    reply = manager.respond("my knee has been hurting all morning", "positive",
                            DialogueContext())
    assert reply.care == "pain" and "knee" in reply.text and "the nurse" in reply.text
    assert "!" not in reply.text


def test_without_staff_the_family_is_called(tmp_path) -> None:
    alone = DialogueManager(QABot.offline(out_dir=tmp_path), talk=CompanionTalk.load())
    reply = alone.respond("I fell over in the bathroom this morning", "positive",
                          DialogueContext())
    assert reply.care == "fall" and "your family" in reply.text and "nurse" not in reply.text


def test_follow_ups_stay_on_the_topic_and_nothing_is_said_twice(
        manager: DialogueManager) -> None:
    ctx = DialogueContext()
    lines = ["It's a year today since I lost my husband.",
             "He loved his roses, he'd be out in the garden every morning.",
             "I miss the way he laughed at his own jokes.",
             "He was a good man, he always looked after me."]
    replies = [manager.respond(line, "positive", ctx) for line in lines]
    assert all(r.route == "companion" and r.act == "loss" for r in replies)
    assert all(re.search(r"\b(?:husband|he|him|his)\b", r.text) for r in replies)
    sentences = [s for r in replies for s in re.split(r"(?<=[.?!])\s+", r.text)]
    assert len(sentences) == len(set(sentences))


def test_a_question_leaves_the_topic(manager: DialogueManager) -> None:
    ctx = DialogueContext()
    manager.respond("my wife passed away last spring", "positive", ctx)
    reply = manager.respond("what time is it?", "positive", ctx)
    assert reply.route == "time"


def test_asked_for_a_story_the_robot_tells_one(manager: DialogueManager) -> None:
    ctx = DialogueContext()
    first = manager.respond("tell me a story", "positive", ctx)
    second = manager.respond("tell me another story", "positive", ctx)
    stories = load_acts_config().entertain.stories
    told = [s for s in stories if s in first.text or s in second.text]
    assert len(told) == 2


def test_the_speaker_is_heard_back_in_their_own_words() -> None:
    assert reflect("My hip's playing up again") == "your hip's playing up again"
    assert reflect("I was a teacher. Forty years of it!") == "you were a teacher"
    assert reflect("the weather is nice") == ""


def test_a_reply_template_with_an_unknown_slot_is_refused(tmp_path) -> None:
    bad = tmp_path / "acts.yaml"
    bad.write_text("acts:\n  thanks:\n    ack:\n      any: ['You are welcome, {nmae}.']\n"
                   "    ask: {any: []}\n    offer: []\n    go_on: {any: []}\n")
    with pytest.raises(ConfigError, match="nmae"):
        load_acts_config(bad)


def _household(tmp_path: Path, talk: CompanionTalk, memory_file: Path) -> DialogueManager:
    """A run's dialogue with the household memory of ``memory_file``."""
    manager = DialogueManager(QABot.offline(out_dir=tmp_path), talk=talk)
    manager.memory = load_memory(memory_file, "home")
    return manager


def test_a_visit_told_in_one_run_is_asked_about_in_the_next(talk: CompanionTalk,
                                                            tmp_path: Path) -> None:
    file = tmp_path / "memory.json"
    first = _household(tmp_path, talk, file)
    told = first.respond("My daughter Susan is coming to see me on Sunday.", "positive",
                         first.context_of("Irene"), person="Irene")
    assert told.remembered == ("visit", "family")
    save_memory(first.memory, file)
    again = _household(tmp_path, talk, file)
    hello = again.respond("Good morning.", "positive", again.context_of("Irene"),
                          person="Irene")
    assert "Is your daughter Susan still coming on Sunday?" in hello.text
    other = again.respond("Good morning.", "positive", again.context_of("Walter"),
                          person="Walter")
    assert "Susan" not in other.text                    # what Irene told is hers
    later = again.respond("Hello again.", "positive", again.context_of("Irene"),
                          person="Irene")
    assert "Susan" not in later.text                    # asked once


def test_forget_that_forgets_the_last_thing_told(talk: CompanionTalk, tmp_path: Path) -> None:
    file = tmp_path / "memory.json"
    manager = _household(tmp_path, talk, file)
    ctx = manager.context_of("Walter")
    manager.respond("My knee is really sore today.", "positive", ctx, person="Walter")
    assert [f.kind for f in manager.memory.facts["Walter"]] == ["ailment"]
    reply = manager.respond("Actually, forget that.", "positive", ctx, person="Walter")
    assert reply.route == "forget" and manager.memory.facts["Walter"] == []
    save_memory(manager.memory, file)
    assert load_memory(file, "home").facts["Walter"] == []


def test_in_the_day_room_grief_is_met_and_pain_raises_a_care_alert(tmp_path: Path) -> None:
    """worlds/day_room_morning.yaml, its first 140 s: Dorothy, a year widowed, gets the
    robot's own replies about her husband over three lines; Walter's knee raises a care
    alert that brings in the nurse (the world has staff), counted in the metrics."""
    from app.report import interaction_metrics
    from app.run import build_run
    from sim.scenario import load_scenario

    scenario = load_scenario(Path(__file__).resolve().parents[1] / "worlds"
                             / "day_room_morning.yaml").model_copy(update={"duration": 140.0})
    household = build_run(scenario, tmp_path)
    with household.sim:
        for _ in range(round(scenario.duration / scenario.step)):
            household.tree.tick()
    events = household.ctx.events.events
    says = [e for e in events if e["kind"] == "say" and e.get("to") == "Dorothy"]
    assert [e["act"] for e in says] == ["loss"] * 3 and all(e["route"] == "companion"
                                                            for e in says)
    assert all("!" not in e["text"] for e in says)
    walter = next(e for e in events if e["kind"] == "say" and e.get("to") == "Walter")
    assert "knee" in walter["text"] and "the nurse" in walter["text"]
    metrics = interaction_metrics(events)
    assert metrics["care_alerts_by"] == {"Walter pain": 1}
    assert metrics["feelings_heard"] >= 2          # her grief and his pain, read from the words


def test_memory_show_lists_what_each_person_told(talk: CompanionTalk, tmp_path: Path,
                                                 capsys) -> None:
    from app.cli import main

    file = tmp_path / "memory.json"
    manager = _household(tmp_path, talk, file)
    manager.respond("I used to be a train driver, you know.", "positive",
                    manager.context_of("Albert"), person="Albert")
    save_memory(manager.memory, file)
    assert main(["memory", "show", str(file)]) == 0
    assert "Albert told: job: a train driver" in capsys.readouterr().out


def test_train_acts_fits_heads_that_the_robot_loads(tmp_path: Path) -> None:
    """`companion train acts --keep-encoder` on a small set of lines (the shipped encoder
    copied beside it): the heads and their figures are written, and the robot reads with them."""
    import shutil

    from app.cli import main
    from dialogue.acts.model import ActModel

    shipped = load_acts_config().resolved_model_dir()
    for name in ("encoder.onnx", "tokenizer.json"):
        shutil.copy(shipped / name, tmp_path / name)
    rows = load_act_lines(DATA / "acts_train.tsv")
    small = [r for act in ("loss", "unwell", "greeting") for r in
             [r for r in rows if r[0] == act][:20]]
    lines = tmp_path / "lines.tsv"
    lines.write_text("".join(f"{a}\t{c}\t{t}\n" for a, c, t in small))
    config = tmp_path / "acts.yaml"
    config.write_text(f"training:\n  training_file: {lines}\n")
    assert main(["train", "acts", "--keep-encoder", "--out", str(tmp_path),
                 "--config", str(config)]) == 0
    cfg = load_acts_config(config).model_copy(update={"model_dir": tmp_path})
    model = ActModel.load(cfg)
    assert set(model.acts.labels) == {"loss", "unwell", "greeting", "question"}
    assert model.read("good morning to you").act == "greeting"


def test_a_recall_question_with_an_unknown_slot_is_refused(tmp_path) -> None:
    bad = tmp_path / "acts.yaml"
    bad.write_text("recall:\n  visit: ['Is {sayd} still coming?']\n")
    with pytest.raises(ConfigError, match="sayd"):
        load_acts_config(bad)


def test_a_broken_heads_file_is_refused_by_name(tmp_path) -> None:
    from core.errors import UserError
    from dialogue.acts.model import load_heads

    broken = tmp_path / "acts.npz"
    broken.write_bytes(b"PK\x03\x04 not a whole zip")
    with pytest.raises(UserError, match="not an act model"):
        load_heads(broken)
