"""The mood gate: its bigram language model, the gate's conditions, the fallback's mood
phrases, its config, the held-out conversational lines and `companion eval mood-style`."""

import argparse
import json

import pytest
from style_helpers import one_thread

from core.config_files import ConfigError
from dialogue.style.config import CLASSIFIER_FILE
from dialogue.style.files import load_classifier
from dialogue.style.mood import (
    MoodStyler,
    capital_i,
    content_kept,
    content_words,
    with_numbers,
    with_opening,
)
from dialogue.style.mood_config import load_mood_config
from dialogue.style.ngram import BigramLM, NgramModelError
from dialogue.style.text import numbers, tokenize
from dialogue.style.training.conversation import heldout_lines, training_lines
from dialogue.style.training.mood_cli import run_eval_mood
from dialogue.style.training.mood_lm import ALL_CONVERSATION
from dialogue.style.transfer import DEFAULT_STYLE_MODEL, StyleTransfer

CORPUS = ["the service was quick and friendly .", "i 'm fine , thank you .",
          "the food was cold and the service was slow .", "thank you for asking .",
          "how are you today ?", "i am fine today .", "the staff were friendly .",
          "the service was terrible and the staff were rude ."]


@pytest.fixture(scope="module", autouse=True)
def _one_thread():
    with one_thread():
        yield


@pytest.fixture(scope="module")
def lm():
    return BigramLM.train([s.split() for s in CORPUS * 3], min_count=1)


@pytest.fixture(scope="module")
def judge():
    return load_classifier(DEFAULT_STYLE_MODEL.parent / CLASSIFIER_FILE)[:2]


@pytest.fixture(scope="module")
def transfer():
    return StyleTransfer.load(DEFAULT_STYLE_MODEL)


def styler(lm, judge, transfer, tmp_path, yaml_text=""):
    """The shipped transfer model and judge with the test's bigram model and config."""
    path = tmp_path / "mood.yaml"
    path.write_text(yaml_text)
    return MoodStyler(transfer, *judge, lm, load_mood_config(path))


def test_bigram_probabilities_sum_to_one_and_survive_a_round_trip(lm, tmp_path):
    for prev in ("<s>", "the", "thank", "never-seen"):
        a = lm.ids([prev])[-2] if prev != "<s>" else 0
        assert sum(lm.prob(a, b) for b in range(1, len(lm.words))) == pytest.approx(1.0)
    lm.save(tmp_path / "lm.npz")
    again = BigramLM.load(tmp_path / "lm.npz")
    sentence = ["the", "service", "was", "slow", "."]
    assert again.perplexity(sentence) == pytest.approx(lm.perplexity(sentence))
    assert lm.perplexity(["slow", "the", ".", "was", "service"]) > 2 * lm.perplexity(sentence)


def test_a_bad_bigram_file_is_a_clear_error(tmp_path):
    (tmp_path / "bad.npz").write_bytes(b"not numpy")
    with pytest.raises(NgramModelError, match=r"bad\.npz"):
        BigramLM.load(tmp_path / "bad.npz")
    with pytest.raises(NgramModelError, match=r"missing\.npz"):
        BigramLM.load(tmp_path / "missing.npz")


def test_content_words_are_the_words_that_are_not_stop_words():
    source = ["the", "service", "was", "quick", "and", "friendly", "."]
    assert content_words(source) == {"service", "quick", "friendly"}
    assert content_kept(source, ["the", "service", "was", "slow", "."]) == pytest.approx(1 / 3)
    assert content_kept(["how", "are", "you", "?"], ["where", "?"]) == 1.0


def test_the_gate_rejects_lost_content_and_high_perplexity(lm, judge, transfer, tmp_path):
    gate = styler(lm, judge, transfer, tmp_path)
    source = ["the", "service", "was", "quick", "and", "friendly", "."]
    fluent = ["the", "service", "was", "terrible", "and", "the", "staff", "were", "rude", "."]
    assert gate.side(fluent) == "negative"
    assert "content words" in gate.refusal(source, fluent, "negative")
    keeps = tokenize("the service was terrible and the staff were rude, quick, friendly.")
    scrambled = tokenize("friendly quick service and the rude terrible. the was")
    assert gate.side(scrambled) == "negative" and content_kept(source, scrambled) == 1.0
    assert "never seen" in gate.refusal(source, scrambled, "negative")   # "friendly quick"
    assert gate.unseen_bigrams(source, ["the", "service", "was", "slow", "."]) == []
    any_pair = styler(lm, judge, transfer, tmp_path, "gate: {min_new_bigram_count: 0}\n")
    assert "perplexity" in any_pair.refusal(source, scrambled, "negative")
    assert gate.ratio(source, keeps) < gate.ratio(source, scrambled)
    assert "question" in gate.refusal(["how", "are", "you", "today", "?"],
                                      ["the", "staff", "were", "rude", "today", "!"], "negative")
    assert "judge" in gate.refusal(source, source, "negative")
    invented = ["the", "service", "was", "terrible", "and", "_num_", "quick", "friendly", "."]
    assert "number" in gate.refusal(source, invented, "negative")
    dropped = ["it", "has", "terrible", "steps", "."]
    assert "number" in gate.refusal(["it", "has", "_num_", "steps", "."], dropped, "negative")


def test_numbers_come_back_as_written():
    assert numbers("It's 18:30 on Sunday, 1 June.") == ["18", "30", "1"]   # ":" splits
    assert tokenize("It's 18:30 on Sunday.")[2:5] == ["_num_", ":", "_num_"]
    assert with_numbers(["at", "_num_", "and", "_num_", "_num_"], ["18:30", "1"]) == [
        "at", "18:30", "and", "1", "_num_"]


def test_the_fallback_says_the_reply_after_the_moods_opening(lm, judge, transfer, tmp_path):
    strict = ("gate: {min_content_kept: 1.0, max_perplexity_ratio: 0.01}\n"
              "openings: {negative: ['Sadly,', 'Unfortunately,'], positive: ['Great,']}\n")
    gate = styler(lm, judge, transfer, tmp_path, strict)
    said = gate.style("The staff were friendly.", "negative")
    assert said.source == "fallback" and said.reason is not None
    assert said.text in ("Sadly, the staff were friendly.",
                         "Unfortunately, the staff were friendly.")
    assert said.content_kept == 1.0
    assert gate.translate(["The staff were friendly."], "negative") == [said.text]
    unchanged = gate.style("The staff were friendly.", "positive")
    assert unchanged.source == "unchanged" and unchanged.text == "The staff were friendly."
    assert with_opening("Oh no,", "I'm fine.") == "Oh no, I'm fine."
    assert with_opening("Oh no,", "The staff.") == "Oh no, the staff."
    assert with_opening("Sadly,", "A calendar.") == "Sadly, a calendar."
    assert with_opening("Sadly,", "Canada is a nation.") == "Sadly, Canada is a nation."
    assert capital_i("i think i'm fine, said ian.") == "I think I'm fine, said ian."


def test_a_closing_joins_the_opening_only_when_no_opening_convinces_the_judge(
        lm, judge, transfer, tmp_path):
    weak = ("gate: {min_content_kept: 1.0, max_perplexity_ratio: 0.01}\n"
            "openings: {positive: ['Well,']}\n"
            "closings: {positive: ['I love this great place!']}\n")
    gate = styler(lm, judge, transfer, tmp_path, weak)
    said = gate.style("The food was cold and the service was slow.", "positive")
    assert said.text == "Well, the food was cold and the service was slow. I love this great place!"
    assert said.judged == "positive"


def test_no_mood_phrase_contradicts_the_reply(lm, judge, transfer, tmp_path):
    strict = "gate: {min_content_kept: 1.0, max_perplexity_ratio: 0.01}\n"
    gate = styler(lm, judge, transfer, tmp_path, strict)
    for text, mood in (("I'm sorry that you aren't happy.", "positive"),
                       ("I apologize, but the cable has been down lately.", "positive"),
                       ("Great, thank you.", "negative")):
        said = gate.style(text, mood)
        assert (said.source, said.text) == ("kept", text), said
        assert "contradict" in said.reason
    asked = styler(lm, judge, transfer, tmp_path, strict + "fallback: {questions: false}\n")
    assert asked.style("Would you like some delicious cake?", "negative").source == "kept"
    assert gate.style("Would you like some delicious cake?", "negative").source == "fallback"


@pytest.mark.parametrize("override", [
    "gate: {min_content_kept: 1.5}\n", "gate: {max_perplexity_ratio: 0}\n",
    "openings: {positive: []}\n", "openings: {negative: ['  ']}\n", "gate: {typo: 1}\n",
    "bigram: {discount: 1.0}\n", "gate: {min_new_bigram_count: -1}\n",
    "fallback: {contrary: {positive: ['']}}\n"])
def test_bad_mood_config_is_an_error(tmp_path, override):
    path = tmp_path / "mood.yaml"
    path.write_text(override)
    with pytest.raises(ConfigError):
        load_mood_config(path)


def test_held_out_lines_are_not_training_lines():
    train = training_lines(ALL_CONVERSATION)
    held = heldout_lines(60, train)
    assert len(held) == 60 and len(set(held)) == 60
    assert not {tuple(tokenize(s)) for s in held} & {tuple(s) for s in train}


def test_eval_mood_style_scores_both_moods_and_writes_its_files(tmp_path, capsys):
    args = argparse.Namespace(config=None, limit=20, json=True, out=tmp_path / "eval")
    assert run_eval_mood(args) == 0
    printed = json.loads(capsys.readouterr().out)
    assert printed["lines"] == 20
    for mood in ("negative", "positive"):
        figures = printed[mood]
        assert sum(figures["share"].values()) == pytest.approx(1.0)
        assert 0 <= figures["flip_rate"] <= 1 and 0 <= figures["content_kept"] <= 1
    assert (tmp_path / "eval" / "metrics.json").exists()
    table = (tmp_path / "eval" / "examples.md").read_text().splitlines()
    assert table[0] == "| Unstyled | Positive mood | Negative mood |" and len(table) == 2 + 20
