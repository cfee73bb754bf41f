"""Chit-chat bot: data, shapes and masks, a tiny training run, decoding, resume, bad files.

Training runs on a small synthetic Papaya-format corpus in a temporary folder, so the tests
need neither the real data nor a shipped model; the real data is checked when present.
"""

import argparse
import csv
import os
import random
import signal
from pathlib import Path

import pytest
import torch
import yaml
from test_training_resume import ctrl_c, refuses_changes_and_bad_checkpoints

from core.checkpoint import read_checkpoint
from core.config_files import ConfigError
from core.errors import UserError
from dialogue.chat.batch import batches, make_batch
from dialogue.chat.config import ChatConfig, load_chat_config
from dialogue.chat.decode import banned_ngram_tokens
from dialogue.chat.model import ChatModelError, ChitChatModel
from dialogue.chat.pool import pool_path, read_pool
from dialogue.chat.seq2seq import Seq2Seq
from dialogue.chat.text import detokenize, tokenize
from dialogue.chat.training.cli import METRIC_KEYS, chat_metrics, run_train
from dialogue.chat.training.data import load_chat_data, read_chatterbot
from dialogue.chat.training.evaluate import distinct_n, perplexity, unigram_perplexity
from dialogue.chat.training.train import train
from textnets.vocab import UNK, Vocab

THINGS = ["music", "dogs", "cats", "pizza", "rain", "books", "football", "movies", "trains",
          "flowers", "robots", "coffee", "tea", "snow", "games", "dancing"]
NAMES = ["ann", "bob", "carl", "dora", "eve", "fred", "gina", "hugo", "iris", "jack"]
TINY = """
data: {{papaya_dir: {dir}, chatterbot: false, min_count: 1, seed: 3}}
model: {{embedding: 32, hidden: 48, layers: 2, dropout: 0.1}}
train: {{threads: 1, epochs: {epochs}, batch_size: 16, learning_rate: 0.01, log_every: 5,
        early_stop: null}}
decode: {{beam_size: 3, max_len: 12}}
"""


def write_corpus(folder: Path, n_convs: int = 60, seed: int = 0) -> Path:
    """Papaya-format conversations with learnable replies and a few traps."""
    rng = random.Random(seed)
    folder.mkdir(parents=True, exist_ok=True)
    blocks = []
    for c in range(n_convs):
        thing, name = THINGS[c % len(THINGS)], NAMES[c % len(NAMES)]
        lines = [f"Q: Do you like {thing} , conv{c} ?", f"A: Yes , I like {thing} a lot .",
                 f"Q: My friend {name} likes {thing} too , conv{c} .",
                 f"A: Say hello to {name} from me ! _func_val_show_picture_para1_{name}",
                 f"Q: What time is it , conv{c} ?", "A: _func_val_get_time"]
        if rng.random() < 0.5:
            lines += [f"Q: Tell me about {thing} , conv{c} .",
                      f"A: I think {thing} make people happy ."]
        blocks.append("\n".join(lines))
    blocks.append("Q: Hello !\nA: Hi there !\nQ: Hello !\nA: Hi there !\nQ: Hello !\nA: Hey !")
    (folder / "synthetic_new.txt").write_text("\n===\n".join(blocks) + "\n")
    return folder


def tiny_config(tmp: Path, folder: Path, epochs: int = 6) -> ChatConfig:
    path = tmp / f"tiny{epochs}.yaml"
    path.write_text(TINY.format(dir=folder, epochs=epochs))
    return load_chat_config(path)


@pytest.fixture(scope="module")
def trained(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("chat")
    cfg = tiny_config(tmp, write_corpus(tmp / "papaya"))
    summary = train(cfg, tmp / "run", progress=False)
    return cfg, tmp / "run", summary


def test_tokenize_matches_papaya_style():
    assert tokenize("I'm sure you don't know what's Sub-Zero's name, can't you?") == [
        "i", "'m", "sure", "you", "do", "n't", "know", "what", "'s", "sub-zero", "'s", "name",
        ",", "ca", "n't", "you", "?"]
    assert tokenize("I do n't know ``it'' _unk_ .") == ["i", "do", "n't", "know", '"', "it",
                                                          '"', UNK, "."]
    assert detokenize(tokenize("i'm fine. i can't wait!")) == "I'm fine. I can't wait!"


def test_loading_strips_functions_drops_and_dedupes(tmp_path):
    data = load_chat_data(tiny_config(tmp_path, write_corpus(tmp_path / "p")).data)
    pairs = [p for split in data.splits.values() for p in split]
    assert not any(t.startswith("_func_val") for p in pairs for side in p for t in side)
    assert (tuple(tokenize("My friend ann likes music too , conv0 .")),
            tuple(tokenize("Say hello to ann from me !"))) in pairs
    assert len({src for src, _ in pairs}) == len(pairs)  # one reply per utterance
    assert [src for src, _ in pairs].count(("hello", "!")) == 1
    c = data.counts["papaya"]
    assert c["dropped_empty_or_slot"] == 60  # the function-only time answers
    assert c["dropped_duplicate_pair"] == 1 and c["dropped_duplicate_input"] == 1


def test_test_split_holds_out_whole_conversations(tmp_path):
    data = load_chat_data(tiny_config(tmp_path, write_corpus(tmp_path / "p")).data)
    convs = {k: {t for src, _ in v for t in src if t.startswith("conv")}
             for k, v in data.splits.items()}
    assert convs["test"] and convs["valid"] and convs["train"]
    assert not convs["test"] & convs["train"] and not convs["valid"] & convs["train"]
    assert not convs["test"] & convs["valid"]


def test_real_data_has_no_leakage():
    pytest.importorskip("chatterbot_corpus")
    cfg = load_chat_config()
    if cfg.data.resolved_papaya() is None or not cfg.data.resolved_papaya().is_dir():
        pytest.skip("Papaya data not present")
    data = load_chat_data(cfg.data)
    train_inputs = {src for src, _ in data.splits["train"]}
    assert not any(src in train_inputs for src, _ in data.splits["test"])
    assert not any(src in train_inputs for src, _ in data.splits["valid"])
    assert data.counts["split"]["test"] > 100 and data.counts["chatterbot"]["kept"] > 100


def test_chatterbot_corpus_is_read():
    pytest.importorskip("chatterbot_corpus")
    convs = read_chatterbot(exclude=["coding"])
    assert convs and not any(c.source == "chatterbot/coding" for c in convs)
    assert all(isinstance(q, str) and isinstance(a, str) for c in convs for q, a in c.pairs)


def small_net(vocab_size: int = 40) -> Seq2Seq:
    torch.manual_seed(0)
    cfg = load_chat_config().model.model_copy(update={"embedding": 16, "hidden": 24})
    return Seq2Seq(vocab_size, cfg).eval()


def test_padding_does_not_change_the_loss():
    vocab = Vocab(["<pad>", "<bos>", "<eos>", "<unk>", *"abcdefghij"])
    pairs = [(("a", "b", "c", "d", "e"), ("f", "g")), (("h",), ("i", "j", "a", "b"))]
    net = small_net(len(vocab))
    together, n = net.token_nll(make_batch(pairs, vocab))
    alone = [net.token_nll(make_batch([p], vocab)) for p in pairs]
    assert n == sum(k for _, k in alone) == 2 + 1 + 4 + 1
    assert torch.allclose(together, sum(s for s, _ in alone), atol=1e-5)


def test_attention_weights_sum_to_one_and_skip_padding():
    vocab = Vocab(["<pad>", "<bos>", "<eos>", "<unk>", *"abcdefghij"])
    batch = make_batch([(("a", "b", "c"), ("d", "e")), (("f",), ("g",))], vocab)
    net = small_net(len(vocab))
    enc, state = net.encode(batch.src, batch.src_mask)
    logits, _, weights = net.decode(batch.tgt_in, state, enc, batch.src_mask)
    assert logits.shape == (2, 3, len(vocab)) and weights.shape == (2, 3, 3)
    assert torch.allclose(weights.sum(-1), torch.ones(2, 3))
    assert torch.all(weights[1, :, 1:] == 0)
    step_logits, _ = net.step(batch.tgt_in[:, 0], state, enc, batch.src_mask)
    assert torch.allclose(step_logits, logits[:, 0], atol=1e-5)


def test_tiny_training_lowers_loss_and_beats_unigram(trained):
    cfg, run, summary = trained
    rows = list(csv.DictReader((run / "eval_log.csv").open()))
    ppl = [float(r["train_perplexity"]) for r in rows]
    assert ppl[-1] < ppl[0] / 3
    model = ChitChatModel.load(run / "chat.pt")
    train_pairs = load_chat_data(cfg.data).splits["train"]
    assert perplexity(model.net, train_pairs, model.vocab) < unigram_perplexity(
        train_pairs, train_pairs, model.vocab) / 3
    assert summary["best_valid_perplexity"] == pytest.approx(
        min(float(r["valid_perplexity"]) for r in rows), abs=0.01)


def test_beam_search_and_sampling_give_clean_replies(trained):
    _, run, _ = trained
    model = ChitChatModel.load(run / "chat.pt")
    for text in ("Do you like dogs?", "hello", "", "zzz qqq " * 100):
        reply = model.reply(text)
        toks = tokenize(reply)
        assert reply and UNK not in toks
        grams = [tuple(toks[i:i + 3]) for i in range(len(toks) - 2)]
        assert len(grams) == len(set(grams))
    assert "like" in model.reply("Do you like dogs , conv3 ?").lower()
    sampler = ChitChatModel.load(run / "chat.pt", method="sample", seed=1, top_p=0.8)
    assert sampler.reply("Do you like tea?")
    assert banned_ngram_tokens([5, 6, 7, 5, 6], 3) == {7}
    assert banned_ngram_tokens([5, 6], 3) == set()
    assert distinct_n([["a", "b"], ["a", "c"]], 1) == 0.75


def test_model_plugs_into_the_dialogue_manager(trained):
    from dialogue.manager import ChitChat, DialogueContext, DialogueManager

    model = ChitChatModel.load(trained[1] / "chat.pt")
    assert isinstance(model, ChitChat)
    ctx = DialogueContext(mode="chitchat")
    reply = DialogueManager(chitchat=model).respond("Do you like cats?", "positive", ctx)
    assert reply.route == "chitchat" and reply.text


def lengthen(run: Path, epochs: int) -> None:
    """Change a run's own configuration on purpose: train it for ``epochs`` in all."""
    path = run / "resolved_config.yaml"
    stored = yaml.safe_load(path.read_text())
    stored["train"]["epochs"] = epochs
    path.write_text(yaml.safe_dump(stored))


def test_checkpoint_resume_matches_an_uninterrupted_run(tmp_path, monkeypatch):
    folder = write_corpus(tmp_path / "p", n_convs=20)
    train(tiny_config(tmp_path, folder, epochs=2), tmp_path / "straight", progress=False)
    train(tiny_config(tmp_path, folder, epochs=1), tmp_path / "split", progress=False)
    with pytest.raises(FileExistsError):
        train(tiny_config(tmp_path, folder, epochs=2), tmp_path / "split", progress=False)
    with pytest.raises(UserError, match=r"train\.epochs: run has 1, the configuration given"):
        train(tiny_config(tmp_path, folder, epochs=2), tmp_path / "split", resume=True,
              progress=False)
    lengthen(tmp_path / "split", 2)
    train(tiny_config(tmp_path, folder, epochs=2), tmp_path / "split", resume=True,
          progress=False)
    a = torch.load(tmp_path / "straight" / "checkpoint.pt", weights_only=True)["net"]
    b = torch.load(tmp_path / "split" / "checkpoint.pt", weights_only=True)["net"]
    assert all(torch.allclose(a[k], b[k], atol=1e-6) for k in a)
    rows = list(csv.DictReader((tmp_path / "split" / "eval_log.csv").open()))
    assert [r["epoch"] for r in rows] == ["1", "2"]

    calls = {"n": 0}
    real_step = torch.optim.Adam.step

    def interrupting_step(self, *args, **kwargs):  # Ctrl-C in the middle of epoch 2
        calls["n"] += 1
        if calls["n"] == 5:
            os.kill(os.getpid(), signal.SIGINT)
        return real_step(self, *args, **kwargs)

    cfg = tiny_config(tmp_path, folder, epochs=2)
    with monkeypatch.context() as m, ctrl_c():
        m.setattr(torch.optim.Adam, "step", interrupting_step)
        with pytest.raises(KeyboardInterrupt):
            train(cfg, tmp_path / "ctrl-c", progress=False)
    assert read_checkpoint(tmp_path / "ctrl-c" / "checkpoint.pt")["counters"][1] == 5
    train(cfg, tmp_path / "ctrl-c", resume=True, progress=False)
    c = torch.load(tmp_path / "ctrl-c" / "checkpoint.pt", weights_only=True)
    straight = torch.load(tmp_path / "straight" / "checkpoint.pt", weights_only=True)
    assert c["counters"] == straight["counters"] and c["counters"][1] > 4
    assert all(torch.allclose(a[k], c["net"][k], atol=1e-6) for k in a)
    for log in ("train_log.csv", "eval_log.csv"):  # no row twice, the same rows
        assert logged(tmp_path / "ctrl-c" / log) == logged(tmp_path / "straight" / log)


def logged(path: Path) -> list[dict[str, str]]:
    """A log's rows without their wall times."""
    return [{k: v for k, v in r.items() if k != "wall_s"}
            for r in csv.DictReader(path.open())]


def test_a_resume_keeps_the_run_config_and_refuses_an_unreadable_checkpoint(tmp_path, trained,
                                                                           capsys):
    other = tmp_path / "other.yaml"
    other.write_text(TINY.format(dir=trained[0].data.papaya_dir, epochs=2))
    refuses_changes_and_bad_checkpoints(
        ["train", "chat", "--no-progress"], trained[1], tmp_path / "run",
        ["--config", str(other)], "train.epochs: run has 6, --config gives 2", capsys)


def test_missing_corrupt_and_mismatched_model_files(tmp_path, trained):
    with pytest.raises(ChatModelError, match="not found") as err:
        ChitChatModel.load(tmp_path / "nope.pt")
    assert isinstance(err.value, UserError)
    bad = tmp_path / "bad.pt"
    bad.write_bytes(b"not a checkpoint at all")
    with pytest.raises(ChatModelError, match="not a readable"):
        ChitChatModel.load(bad)
    torch.save({"format": "something-else"}, bad)
    with pytest.raises(ChatModelError, match="not a chit-chat model"):
        ChitChatModel.load(bad)
    blob = torch.load(trained[1] / "chat.pt", weights_only=True)
    blob["config"]["model"]["hidden"] = 64
    torch.save(blob, bad)
    with pytest.raises(ChatModelError, match="inconsistent"):
        ChitChatModel.load(bad)
    with pytest.raises(ChatModelError):
        chat_metrics(tmp_path / "nope.pt")


def test_config_rejects_unknown_keys(tmp_path):
    path = tmp_path / "c.yaml"
    path.write_text("train: {epochs: 3, learning_rat: 0.1}\n")
    with pytest.raises(ConfigError, match=r"train\.learning_rat: unknown key"):
        load_chat_config(path)


def test_cli_trains_exports_and_measures(tmp_path):
    folder = write_corpus(tmp_path / "p", n_convs=20)
    (tmp_path / "c.yaml").write_text(TINY.format(dir=folder, epochs=1))
    args = argparse.Namespace(config=tmp_path / "c.yaml", out=tmp_path / "run", resume=False,
                              export=tmp_path / "models" / "chat.pt", no_progress=True)
    assert run_train(args) == 0
    metrics = chat_metrics(tmp_path / "models" / "chat.pt")
    assert set(METRIC_KEYS) <= set(metrics)
    assert metrics["unigram_perplexity"] > 1 and 0 <= metrics["distinct_1"] <= 1
    assert "| person | reference reply | beam search alone | ranked (the robot) |" in \
        metrics["examples_markdown"]
    assert set(metrics["decodings"]) == {"beam", "ranked"}
    assert 0 <= metrics["decodings"]["beam"]["generic_share"] <= 1
    data = load_chat_data(load_chat_config(tmp_path / "c.yaml").data)
    stored = ChitChatModel.load(tmp_path / "models" / "chat.pt").config["data"]
    pool = read_pool(pool_path(tmp_path / "models" / "chat.pt"), stored,  # exported beside
                     tmp_path / "p").pairs
    assert pool == data.splits["train"]
    assert not {src for src, _ in pool} & {src for src, _ in data.splits["test"]}
    assert next(iter(batches([], Vocab.build([], 1), 4)), None) is None


def test_shipped_chat_model_meets_its_bars() -> None:
    """The committed chit-chat model beats the unigram baseline 3x on held-out pairs."""
    from dialogue.chat.config import DEFAULT_CHAT_MODEL
    from dialogue.chat.model import ChitChatModel
    from dialogue.chat.training.cli import chat_metrics
    from dialogue.manager import DialogueContext

    metrics = chat_metrics(DEFAULT_CHAT_MODEL)
    assert metrics["chat_perplexity"] * 3 <= metrics["unigram_perplexity"]
    assert metrics["model_mb"] <= 25
    reply = ChitChatModel.load(DEFAULT_CHAT_MODEL).reply("how are you?", DialogueContext())
    assert reply.strip() and len(reply.split()) <= 30
