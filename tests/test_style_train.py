"""Style transfer: a tiny seeded training run, resume, model files and the command line."""

import argparse
import csv
import io
import itertools
import json
import os
import signal

import pytest
import torch
from style_helpers import one_thread, tiny_config, write_corpus
from test_training_resume import refuses_changes_and_bad_checkpoints
from torch import nn

from core.checkpoint import read_checkpoint
from core.errors import UserError
from core.signals import Terminated
from dialogue.style.config import load_style_config
from dialogue.style.files import StyleModelError
from dialogue.style.training import cli as style_cli
from dialogue.style.training import train as style_train
from dialogue.style.transfer import (
    DEFAULT_STYLE_MODEL,
    StyleTransfer,
    readable,
    replace_unknown,
)
from textnets.loop import Run
from textnets.vocab import SPECIALS, Vocab


@pytest.fixture(scope="module", autouse=True)
def _one_thread():
    with one_thread():
        yield


@pytest.fixture(scope="module")
def data_dir(tmp_path_factory):
    return write_corpus(tmp_path_factory.mktemp("yelp"))


@pytest.fixture(scope="module")
def trained(tmp_path_factory, data_dir):
    """A tiny model trained through the CLI handler and exported to a model folder."""
    root = tmp_path_factory.mktemp("run")
    args = argparse.Namespace(config=tiny_config(root, data_dir), out=root / "out",
                              resume=False, data=None, no_style_autoencoder=False,
                              export=root / "models", no_progress=True, judges=None, init=None)
    assert style_cli.run_train(args) == 0
    return root


# --- training -----------------------------------------------------------------------------

def read_log(path):
    with path.open() as fh:
        return list(csv.DictReader(fh))


def test_tiny_training_lowers_each_loss(trained):
    out = trained / "out"
    checks = {"classifier": ["loss"], "lm": ["nll"], "pretrain": ["style", "lm_enc", "lm_gen"],
              "reconstruct": ["rec"], "adversarial": ["rec", "cycle", "disc"]}
    for phase, fields in checks.items():
        rows = read_log(out / f"log_{phase}.csv")
        for f in fields:
            assert float(rows[-1][f]) < float(rows[0][f]), (phase, f)
    summary = json.loads((out / "summary.json").read_text())
    assert summary["classifier"]["test_accuracy"] > 0.9
    steps = [r["step"] for r in read_log(out / "valid_log.csv")]
    assert steps == ["0", "10", "20", "30", "40", "50", "60"]  # 0: the warm-up model
    assert {p.name for p in (trained / "models").iterdir()} == {"style.pt", "classifier.pt",
                                                                "lm.pt"}


def test_existing_run_needs_resume(trained):
    args = argparse.Namespace(config=trained / "tiny.yaml", out=trained / "out", resume=False,
                              data=None, no_style_autoencoder=False, export=None,
                              no_progress=True, judges=None, init=None)
    with pytest.raises(FileExistsError):
        style_cli.run_train(args)


def test_an_ablation_reuses_the_judges_of_an_earlier_run(trained, tmp_path):
    args = argparse.Namespace(config=trained / "tiny.yaml", out=tmp_path / "ablation",
                              resume=False, data=None, no_style_autoencoder=True, export=None,
                              no_progress=True, judges=trained / "out", init=None)
    assert style_cli.run_train(args) == 0
    for name in ("classifier.pt", "lm.pt"):
        assert (tmp_path / "ablation" / name).read_bytes() == (trained / "out" / name).read_bytes()
    assert not (tmp_path / "ablation" / "log_classifier.csv").exists()
    summary = json.loads((tmp_path / "ablation" / "summary.json").read_text())
    assert summary["classifier"]["test_accuracy"] > 0.9
    assert (tmp_path / "ablation" / "style.pt").exists()


def test_fine_tuning_starts_from_a_model_and_adds_the_robots_lines(trained, tmp_path):
    config = tmp_path / "tune.yaml"
    config.write_text((trained / "tiny.yaml").read_text()
                      + "\nconversation: {chat: true, qa: true, repeat: 2}\n")
    args = argparse.Namespace(config=config, out=tmp_path / "tune", resume=False, data=None,
                              no_style_autoencoder=False, export=None, no_progress=True,
                              judges=trained / "out", init=trained / "models" / "style.pt")
    assert style_cli.run_train(args) == 0
    summary = json.loads((tmp_path / "tune" / "summary.json").read_text())
    lines = summary["conversation"]["lines"]
    assert lines > 500 and 0 < summary["conversation"]["positive"] < lines
    assert summary["conversation"]["repeat"] == 2 and summary["conversation"]["kept"] == lines
    start = torch.load(trained / "models" / "style.pt", weights_only=True)["state_dict"]
    first = torch.load(tmp_path / "tune" / "style.pt", weights_only=True)
    assert first["meta"]["step"] >= 0 and set(first["state_dict"]) == set(start)
    other = argparse.Namespace(**{**vars(args), "out": tmp_path / "other",
                                  "init": DEFAULT_STYLE_MODEL})
    with pytest.raises(StyleModelError, match="another vocabulary"):
        style_cli.run_train(other)


def test_interrupted_training_resumes_to_the_same_model(tmp_path, data_dir, monkeypatch):
    cfg = load_style_config(tiny_config(tmp_path, data_dir, adv=12))
    cfg = cfg.model_copy(update={"model": cfg.model.model_copy(
        update={"style_autoencoder": False})})  # the ablation trains too
    style_train.train(cfg, tmp_path / "whole", progress=False)
    real, calls = style_train.transfer_losses, itertools.count()

    def interrupt(*a, **k):
        if len(a) == 4 and next(calls) == 7:  # SIGTERM in the 8th adversarial step
            os.kill(os.getpid(), signal.SIGTERM)
        return real(*a, **k)

    monkeypatch.setattr(style_train, "transfer_losses", interrupt)
    with pytest.raises(Terminated):
        style_train.train(cfg, tmp_path / "cut", progress=False)
    assert read_checkpoint(tmp_path / "cut" / "checkpoint.pt")["step"] == 8  # the 8th finished
    monkeypatch.setattr(style_train, "transfer_losses", real)
    style_train.train(cfg, tmp_path / "cut", resume=True, progress=False)
    a = torch.load(tmp_path / "whole" / "style.pt", weights_only=True)["state_dict"]
    b = torch.load(tmp_path / "cut" / "style.pt", weights_only=True)["state_dict"]
    assert all(torch.equal(a[k], b[k]) for k in a)
    assert [r["step"] for r in read_log(tmp_path / "cut" / "log_adversarial.csv")] == ["10", "12"]
    assert [r["step"] for r in read_log(tmp_path / "cut" / "valid_log.csv")] == ["0", "10", "12"]
    for log in ("valid_log.csv", "log_adversarial.csv"):   # the same rows, averages too
        cut, whole = (read_log(tmp_path / run / log) for run in ("cut", "whole"))
        assert [r | {"wall_s": ""} for r in cut] == [r | {"wall_s": ""} for r in whole]


def test_a_resume_keeps_the_run_config_and_refuses_an_unreadable_checkpoint(trained, tmp_path,
                                                                           capsys):
    refuses_changes_and_bad_checkpoints(
        ["train", "style", "--no-progress"], trained / "out", tmp_path,
        ["--no-style-autoencoder"],
        "model.style_autoencoder: run has True, --no-style-autoencoder gives False", capsys,
        (trained / "out" / "checkpoint.pt").read_bytes()[:999])


# --- loading, translating, the command line ----------------------------------------------

def test_missing_and_corrupt_weights_are_user_errors(tmp_path, trained):
    with pytest.raises(StyleModelError, match="not found"):
        StyleTransfer.load(tmp_path / "none.pt")
    (tmp_path / "bad.pt").write_bytes(b"not a checkpoint")
    with pytest.raises(StyleModelError, match="not a readable model file"):
        StyleTransfer.load(tmp_path / "bad.pt")
    with pytest.raises(StyleModelError, match="not a style file"):
        StyleTransfer.load(trained / "models" / "classifier.pt")
    assert issubclass(StyleModelError, UserError)


def test_translate_keeps_one_output_per_input_and_the_confidence_rule(trained):
    st = StyleTransfer.load(trained / "models" / "style.pt")
    inputs = ["the food was cold .", "", "The pizza was stale!"]
    details = st.translate_detailed(inputs, "positive")
    assert len(details) == 3 and details[1].text == ""
    for d, src in zip(details, inputs, strict=True):
        assert d.text == (src if d.kept_original else readable(d.transferred.split(), src))
    assert readable(["it", "'s", "good", "!"], "The pizza") == "It's good!"
    assert readable(["it", "'s", "good", "!"], "the pizza") == "it's good!"
    assert "cold" in st.style_words and "food" not in st.style_words
    assert st.content_overlap(["the", "food", "was", "cold"], ["the", "food", "is", "hot"]) == 1
    assert st.content_overlap(["the", "food", "was", "cold"], ["my", "day", "was", "ok"]) == 0
    with pytest.raises(ValueError, match="to must be"):
        st.translate(["x"], "sarcastic")


def test_unknown_words_are_copied_from_the_source():
    v = Vocab([*SPECIALS, "the", "was"])
    assert replace_unknown(["the", "<unk>", "was", "<unk>"], ["the", "zorb", "was"], v) == [
        "the", "zorb", "was"]


def parser_for(hook):
    parser = argparse.ArgumentParser()
    sub = parser.add_subparsers(dest="cmd", required=True)
    getattr(style_cli, hook)(sub)
    return parser


def test_cli_style_sentences_and_batch_mode(trained, capsys, monkeypatch):
    model = str(trained / "models" / "style.pt")
    args = parser_for("add_commands").parse_args(
        ["style", "--to", "positive", "--model", model, "the food was cold ."])
    status = args.func(args)   # 1 when the tiny model's translation fails a check
    out, err = capsys.readouterr()
    assert len(out.splitlines()) == 1 and status == (1 if "printed unchanged" in err else 0)
    monkeypatch.setattr("sys.stdin", io.StringIO("the food was cold .\n\nrude staff .\n"))
    args = parser_for("add_commands").parse_args(["style", "--to", "negative", "--model", model])
    assert args.func(args) in (0, 1)
    assert len(capsys.readouterr().out.splitlines()) == 3
    args = parser_for("add_commands").parse_args(
        ["style", "--to", "negative", "--model", str(trained / "nothing.pt"), "hi"])
    with pytest.raises(StyleModelError):
        args.func(args)


def test_cli_eval_json(trained, capsys):
    args = parser_for("add_eval").parse_args(
        ["style", "--model-dir", str(trained / "models"), "--json", "--limit", "20",
         "--out", str(trained / "eval")])
    assert args.func(args) == 0
    result = json.loads(capsys.readouterr().out)
    assert {"accuracy", "self_bleu", "perplexity", "classifier_accuracy"} <= set(result)
    assert result["sentences"] == 20 and 0 <= result["accuracy"] <= 1
    assert "Table 4.5" in (trained / "eval" / "examples.md").read_text()


def test_resuming_a_checkpoint_of_other_networks_names_the_problem(tmp_path):
    Run(None, tmp_path, {"a": nn.Linear(2, 2)}, resume=False, progress=False).save(None)
    with pytest.raises(UserError, match="holds no b"):
        Run(None, tmp_path, {"a": nn.Linear(2, 2), "b": nn.Linear(2, 2)}, True, False)
    with pytest.raises(UserError, match="a weights do not fit"):
        Run(None, tmp_path, {"a": nn.Linear(3, 3)}, resume=True, progress=False)
