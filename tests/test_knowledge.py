"""Everyday knowledge from WordNet (read in place from the wordnet-base package that
`make setup` installs), the topic a question names, and the knowledge questions' scoring."""

import json
from pathlib import Path

import pytest

from app.cli import main
from dialogue.conversation import load_conversation_config
from dialogue.knowledge_eval import evaluate_knowledge, load_questions, mark
from dialogue.qa.base import DialogueError
from dialogue.qa.encyclopedia import Encyclopedia, clean_gloss
from dialogue.qa.knowledge import KnowledgeBase, answer_information
from dialogue.qa.news import news_topic
from dialogue.qa.text import topic_phrase
from dialogue.qa.wordnet import WordNet


@pytest.fixture(scope="module")
def wn() -> WordNet:
    wordnet = WordNet.load(load_conversation_config().knowledge.wordnet_dir)
    assert wordnet is not None, "WordNet is missing: run `make setup` (package wordnet-base)"
    return wordnet


@pytest.fixture(scope="module")
def enc(wn: WordNet) -> Encyclopedia:
    return Encyclopedia(wn)


def test_wordnet_finds_lemmas_by_binary_search_in_place(wn: WordNet, tmp_path: Path) -> None:
    lemmas = [line.split()[0].replace("_", " ")
              for line in (wn.folder / "index.noun").read_text(encoding="utf-8").splitlines()
              if not line.startswith(" ")]
    for lemma in (lemmas[0], lemmas[len(lemmas) // 2], lemmas[-1], "volcano"):
        assert wn.offsets(lemma), lemma
    assert wn.offsets("volcanox") == () and wn.offsets("") == ()
    assert wn.base_forms("mice") == ["mouse"] and "whale" in wn.base_forms("whales")
    assert wn.base_forms("wrote", "v") == ["write"]
    assert {"wrote", "written", "writes"} <= wn.inflections("write")
    assert WordNet.load(tmp_path) is None  # not installed: the knowledge base answers alone


def test_what_and_who_speak_the_first_gloss_sentence(enc: Encyclopedia) -> None:
    volcano = enc.describe("volcano", asked="a volcano")
    assert volcano.text.startswith("A volcano is ") and "lava" in volcano.text
    einstein = enc.describe("einstein", who=True)
    assert einstein.text.startswith("Albert Einstein was a physicist")  # dates: was
    assert "(" not in einstein.text and ";" not in einstein.text
    assert "genius" not in einstein.text  # a "who" question takes the person's sense
    assert enc.describe("whales", asked="whales").text.startswith("Whales are ")
    assert enc.describe("florbnax") is None
    assert clean_gloss("a b (c d) e; \"an example\"") == "a b e"


@pytest.mark.parametrize(("cue", "thing", "maker"), [
    ("invented", "telephone", "Bell"),           # the inventor's gloss names the thing
    ("invented", "elevator", "Otis"),
    ("invented", "braille", "Louis Braille"),    # named after its maker
    ("author", "hamlet", "Shakespeare"),         # "William Shakespeare's tragedy"
    ("wrote", "the Canterbury Tales", "Chaucer"),
    ("developed", "theory of relativity", "Einstein"),  # develop: formulate(d)
])
def test_who_made_looks_both_ways(enc: Encyclopedia, cue: str, thing: str, maker: str) -> None:
    fact = enc.who_made(cue, thing)
    assert fact is not None and fact.text.startswith("That was ") and maker in fact.text


def test_who_made_needs_a_maker(enc: Encyclopedia) -> None:
    assert enc.who_made("invented", "table") is None  # "More" in a gloss is not Thomas More
    assert enc.who_made("wrote", "glorptastic engine") is None
    assert {"invented", "inventor", "invention"} <= enc.cue_words("invented")


def test_household_knowledge_wins_then_wordnet_then_i_dont_know(enc: Encyclopedia) -> None:
    kb = KnowledgeBase.load()
    pepper = answer_information("What is Pepper?", kb, encyclopedia=enc)
    assert pepper.text == kb.get("pepper").summary
    bell = answer_information("Who invented the telephone?", kb, encyclopedia=enc)
    assert "Bell" in bell.text and bell.tablet.startswith("https://en.wikipedia.org/wiki/")
    unknown = answer_information("Who was Zandor Plimwick?", kb, encyclopedia=enc)
    assert not unknown.found
    assert unknown.text == "I'm sorry, I don't know anything about Zandor Plimwick yet."
    assert not answer_information("What is a volcano?", kb).found  # no WordNet given


@pytest.mark.parametrize(("text", "topic"), [
    ("tell me about the Eiffel Tower", "Eiffel Tower"),
    ("What is a volcano?", "volcano"),
    ("Explain what a black hole is", "black hole"),
    ("who was Albert Einstein", "Albert Einstein"),
    ("Who is the author of Hamlet?", "Hamlet"),
    ("who invented the telephone", "telephone"),
    ("Hey robot, what is the moon made of?", "moon"),
    ("Can you tell me something about Mount Everest, please?", "Mount Everest"),
    ("tell me about it", ""),
    ("explain", ""),
])
def test_topic_of_a_question(text: str, topic: str) -> None:
    assert topic_phrase(text) == topic


@pytest.mark.parametrize(("text", "topic"), [
    ("What's in the news today?", []),
    ("Look, I can still touch the sky! What's in the news today?", []),
    ("any news about the elections?", ["elections"]),
    ("Read me the headlines please", []),
    ("What's going on in politics?", ["politics"]),
    ("Give me the news about the football club", ["football", "club"]),
])
def test_news_topic_table(text: str, topic: list[str]) -> None:
    assert news_topic(text) == topic


def test_knowledge_questions_are_marked_by_keywords(tmp_path: Path,
                                                    capsys: pytest.CaptureFixture) -> None:
    assert mark("A volcano is a mountain", True, ["lava", "mountain"]) == "correct"
    assert mark("A volcano is a vent", True, ["lava"]) == "wrong"
    assert mark("I don't know", False, ["lava"]) == "unanswered"
    assert mark("I don't know", False, ["-"]) == "correct"
    assert len(load_questions()) >= 100
    small = tmp_path / "q.tsv"
    small.write_text("# kind, question, keywords\nthing\tWhat is a volcano?\tlava|mountain\n"
                     "person\tWho was Albert Einstein?\trelativity\n"
                     "none\tWhat is a florbnax?\t-\n", encoding="utf-8")
    result = evaluate_knowledge(small)
    assert result["accuracy"] == 1.0 and result["n"] == 3
    assert main(["eval", "knowledge", "--json", "--questions", str(small)]) == 0
    assert json.loads(capsys.readouterr().out)["marks"] == {"correct": 3}
    small.write_text("thing\tWhat is a volcano?\n", encoding="utf-8")
    with pytest.raises(DialogueError, match=r"q\.tsv:1"):
        load_questions(small)


def test_follow_ups_keep_the_topic(tmp_path: Path) -> None:
    from dialogue.manager import DialogueManager
    from dialogue.qa.bot import QABot

    m = DialogueManager(QABot.offline(out_dir=tmp_path))
    assert m.respond("Who was Albert Einstein?").text.startswith("Albert Einstein was")
    more = m.respond("Tell me more")
    assert more.route == "information" and "light" in more.text  # the gloss's next sentence
    assert m.respond("tell me more about him").text == more.text
    m.respond("What is a volcano?")
    assert m.respond("tell me more about it").text == "That's all I know about it for now."
    m.respond("What time is it?")
    assert m.respond("tell me more").route != "information"
