"""Resuming a training: the run's own configuration, unreadable checkpoints, logs cut back to
the checkpoint, and SIGINT, SIGTERM and SIGKILL in the middle of a tiny policy training (in
this process and as a real `companion train policy` process). The other trainers' own test
files check the same rules on their tiny runs."""

from __future__ import annotations

import contextlib
import csv
import json
import os
import shutil
import signal
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
import torch

from app.cli import main
from core.checkpoint import TrainingFolder, read_checkpoint
from core.errors import UserError
from core.interrupts import stop_point, stop_requests
from core.run_config import differences
from mind.personality import load_personality
from mind.policy.config import load_policy_config
from mind.policy.training import train as policy_train
from mind.policy.training.env import VecHomeostasisEnv

ROOT = Path(__file__).resolve().parents[1]
TINY = """env: {{episode_steps: 200}}
network: {{hidden: [32, 32], head: 16, input_offset: 0.6}}
train: {{num_envs: {envs}, episode_steps: 200, total_transitions: {total}, learning_starts: 50,
        buffer_size: 2000, eval_episodes: 1, eval_every: {eval_every}, checkpoint_every: 40}}
"""
CORRUPT = {"empty": lambda data: b"", "truncated": lambda data: data[: len(data) // 2],
           "random bytes": lambda data: os.urandom(4096)}


def tiny(folder: Path, envs: int = 4, total: int = 400, eval_every: int = 10_000) -> Path:
    """A tiny policy config file (validation only at the end unless ``eval_every``)."""
    path = folder / f"tiny-{envs}-{total}.yaml"
    path.write_text(TINY.format(envs=envs, total=total, eval_every=eval_every))
    return path


def rows(path: Path) -> list[dict[str, str]]:
    """A CSV log's rows, each checked to parse: every field there and a number."""
    with path.open(newline="") as fh:
        reader = csv.DictReader(fh)
        out = list(reader)
    for row in out:
        assert None not in row and all(v is not None for v in row.values()), row
        [float(v) for v in row.values()]
    return out


def without_wall(log: list[dict[str, str]]) -> list[dict[str, str]]:
    return [{k: v for k, v in r.items() if k != "wall_s"} for r in log]


def err_lines(capsys) -> list[str]:
    return capsys.readouterr().err.strip().splitlines()


def refuses_changes_and_bad_checkpoints(command: list[str], run: Path, out: Path,
                                        change: list[str], named: str, capsys,
                                        checkpoint: bytes = b"\x80\x02junk") -> None:
    """Resuming into ``out``, which holds the finished ``run``'s configuration and an
    unreadable ``checkpoint``: the options ``change`` are refused naming the setting
    ``named``, and the checkpoint in one line (exit 2 both)."""
    out.mkdir(exist_ok=True)
    shutil.copy(run / "resolved_config.yaml", out)
    (out / "checkpoint.pt").write_bytes(checkpoint)
    args = [*command, "--out", str(out), "--resume"]
    assert main([*args, *change]) == 2
    assert named in capsys.readouterr().err
    assert main(args) == 2
    lines = err_lines(capsys)
    assert len(lines) == 1 and lines[0].startswith("companion: error: ")
    assert "checkpoint.pt: not a readable checkpoint" in lines[0]


@contextlib.contextmanager
def ctrl_c() -> Iterator[None]:
    """Within the block SIGINT raises KeyboardInterrupt, as typed at a terminal (a test run
    that a script put in the background starts with it ignored, and a training keeps it so)."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


@pytest.fixture(scope="module")
def finished(tmp_path_factory):
    """A finished tiny policy run (4 envs), through the command line."""
    root = tmp_path_factory.mktemp("policy")
    out = root / "run"
    assert main(["train", "policy", "--config", str(tiny(root)), "--out", str(out),
                 "--no-progress"]) == 0
    return root, out


# --- the run's own configuration ---------------------------------------------------------

def test_differences_are_dotted_paths_with_both_values():
    run = {"train": {"num_envs": 16, "hidden": [64, 64]}, "seed": 0, "heat": {"a": 1}}
    given = {"train": {"num_envs": 8, "hidden": [64, 64]}, "seed": 0, "heat": {"b": 1}}
    changed = differences(run, given)
    assert changed[0] == ("train.num_envs", 16, 8)
    assert [path for path, _, _ in changed] == ["train.num_envs", "heat.a", "heat.b"]


def test_a_resume_given_another_config_is_refused_naming_each_key(finished, capsys):
    root, out = finished
    args = ["train", "policy", "--out", str(out), "--no-progress", "--resume"]
    assert main([*args, "--config", str(tiny(root, envs=8))]) == 2
    err = capsys.readouterr().err
    assert "policy.train.num_envs: run has 4, --config gives 8" in err
    assert "network" not in err  # only what differs
    personality = root / "personality.yaml"
    personality.write_text("mood: {threshold: 0.5}\n")
    assert main([*args, "--config", str(tiny(root, envs=8)), "--personality",
                 str(personality)]) == 2
    err = capsys.readouterr().err
    assert "personality.mood.threshold: run has" in err and "--config and --personality give" in err
    assert main([*args, "--config", str(tiny(root))]) == 0  # the same config is fine


def test_a_checkpoint_without_its_config_is_refused(finished, tmp_path, capsys):
    _, out = finished
    (tmp_path / "checkpoint.pt").write_bytes((out / "checkpoint.pt").read_bytes())
    assert main(["train", "policy", "--out", str(tmp_path), "--resume"]) == 2
    assert "has no resolved_config.yaml" in capsys.readouterr().err


@pytest.mark.parametrize("kind", CORRUPT)
def test_an_unreadable_checkpoint_is_one_line_and_exit_2(finished, tmp_path, capsys, kind):
    root, out = finished
    refuses_changes_and_bad_checkpoints(
        ["train", "policy", "--no-progress"], out, tmp_path, ["--config", str(tiny(root, 8))],
        "policy.train.num_envs: run has 4", capsys,
        CORRUPT[kind]((out / "checkpoint.pt").read_bytes()))


def test_a_checkpoint_of_something_else_names_what_it_lacks(tmp_path):
    torch.save({"format": "a model file"}, tmp_path / "checkpoint.pt")
    with pytest.raises(UserError, match="holds no 'wall_s'"):
        TrainingFolder(tmp_path, resume=True)
    torch.save([1, 2], tmp_path / "checkpoint.pt")
    with pytest.raises(UserError, match="holds a list"):
        TrainingFolder(tmp_path, resume=True)


def test_a_resumed_log_drops_rows_past_the_checkpoint_and_rows_cut_short(tmp_path):
    folder = TrainingFolder(tmp_path, resume=False)
    folder.save({})
    (tmp_path / "log.csv").write_text("step,loss\n1,0.5\n2,0.4\n3,0.3\nx,0.2\n4")
    folder = TrainingFolder(tmp_path, resume=True)
    folder.open_log("log.csv", ["step", "loss"], keep=lambda r: int(r[0]) <= 2).close()
    assert (tmp_path / "log.csv").read_text().splitlines() == ["step,loss", "1,0.5", "2,0.4"]


# --- interruptions -----------------------------------------------------------------------

def signal_at(monkeypatch, call: int, sig: signal.Signals) -> None:
    """Send ``sig`` to this process from the ``call``-th step of the training env."""
    real, calls = VecHomeostasisEnv.advance, iter(range(1, 10**9))

    def advance(self):
        if next(calls) == call:
            os.kill(os.getpid(), sig)
        return real(self)

    monkeypatch.setattr(VecHomeostasisEnv, "advance", advance)


def test_sigterm_then_resume_without_config_continues_the_run_exactly(tmp_path, monkeypatch,
                                                                      capsys):
    config = tiny(tmp_path, total=300, eval_every=30)
    cfg = load_policy_config(config)
    policy_train.train(load_personality(), cfg, tmp_path / "straight", progress=False)
    out = tmp_path / "cut"
    with monkeypatch.context() as m:
        signal_at(m, 50, signal.SIGTERM)
        assert main(["train", "policy", "--config", str(config), "--out", str(out),
                     "--no-progress"]) == 143
    line = err_lines(capsys)[-1]
    assert "train policy interrupted (SIGTERM), its checkpoint is kept" in line
    assert line.endswith(f"companion train policy --out {out} --resume")
    assert not (out / "policy.pt").exists()  # the resumed run exports it, as configured
    assert main(["train", "policy", "--out", str(out), "--no-progress", "--resume"]) == 0
    assert torch.load(out / "policy.pt", weights_only=True)["network"]["input_offset"] == 0.6
    for log in ("train_log.csv", "eval_log.csv"):
        assert without_wall(rows(out / log)) == without_wall(rows(tmp_path / "straight" / log))
    episodes = [int(r["episode"]) for r in rows(out / "train_log.csv")]
    assert episodes == list(range(1, len(episodes) + 1))


def test_sigint_in_pretraining_resumes_exactly(tmp_path, monkeypatch):
    cfg = load_policy_config(tiny(tmp_path, total=100))
    cfg = cfg.model_copy(update={"train": cfg.train.model_copy(update={
        "demo_transitions": 200, "demo_pretrain_updates": 30})})
    policy_train.train(load_personality(), cfg, tmp_path / "straight", progress=False)
    real, calls = policy_train.dqn_update, iter(range(1, 10**9))

    def update(*a, **k):
        if next(calls) == 12:
            os.kill(os.getpid(), signal.SIGINT)
        return real(*a, **k)

    with monkeypatch.context() as m, ctrl_c():
        m.setattr(policy_train, "dqn_update", update)
        with pytest.raises(KeyboardInterrupt):
            policy_train.train(load_personality(), cfg, tmp_path / "cut", progress=False)
    assert read_checkpoint(tmp_path / "cut" / "checkpoint.pt")["counters"] == (
        0, 12, 0)
    policy_train.train(load_personality(), cfg, tmp_path / "cut", resume=True, progress=False)
    a = torch.load(tmp_path / "straight" / "policy.pt", weights_only=True)["state_dict"]
    b = torch.load(tmp_path / "cut" / "policy.pt", weights_only=True)["state_dict"]
    assert all(torch.equal(a[k], b[k]) for k in a)


def test_a_sigint_the_process_ignores_stays_ignored():
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        with stop_requests():
            os.kill(os.getpid(), signal.SIGINT)
            stop_point()  # nothing asked
            assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN
    finally:
        signal.signal(signal.SIGINT, previous)


def companion(*args: str) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-m", "app.cli", *args], cwd=ROOT,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)


def wait_for_checkpoint(out: Path, process: subprocess.Popen, after: float = 0.0) -> None:
    """Wait until ``out`` holds a checkpoint written after the time ``after``."""
    deadline = time.monotonic() + 60
    ckpt = out / "checkpoint.pt"
    while not (ckpt.exists() and ckpt.stat().st_mtime > after):
        assert process.poll() is None, process.stderr.read()
        assert time.monotonic() < deadline
        time.sleep(0.05)


def test_a_training_process_killed_then_terminated_resumes_and_finishes(tmp_path):
    out = tmp_path / "run"
    args = ["train", "policy", "--out", str(out), "--no-progress"]
    first = companion(*args, "--config", str(tiny(tmp_path, total=400)))
    wait_for_checkpoint(out, first)
    first.send_signal(signal.SIGKILL)
    assert first.wait() == -signal.SIGKILL
    stamp = (out / "checkpoint.pt").stat().st_mtime
    second = companion(*args, "--resume")
    wait_for_checkpoint(out, second, after=stamp)
    second.send_signal(signal.SIGTERM)
    assert second.wait(timeout=60) == 143
    last = second.stderr.read().strip().splitlines()[-1]
    assert "interrupted (SIGTERM)" in last and last.endswith("--resume")
    third = companion(*args, "--resume")
    assert third.wait(timeout=120) == 0, third.stderr.read()
    log = rows(out / "train_log.csv")
    assert [int(r["episode"]) for r in log] == list(range(1, len(log) + 1))
    rows(out / "eval_log.csv")
    assert json.loads((out / "summary.json").read_text())["transitions"] >= 400
    assert not list(out.glob(".*.tmp")) and not (out / ".lock").exists()
