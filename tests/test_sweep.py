"""`companion sweep` on a real local Ray: runs spread as tasks, a failed run is recorded
while the others finish, a killed driver loses and redoes nothing, and a sweep joins a Ray
head started on loopback with `ray start --head`."""

from __future__ import annotations

import contextlib
import csv
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
from test_training_resume import tiny

from app.cli import main

ROOT = Path(__file__).resolve().parents[1]
RAY = str(Path(sys.executable).with_name("ray"))
SWEEP = [sys.executable, "-m", "app.cli", "sweep"]


def spec(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "spec.yaml"
    path.write_text(text.replace("WORLD", str(ROOT / "worlds" / "living_room.yaml")))
    return path


@pytest.mark.parametrize(("text", "message"), [
    ("worlds: [WORLD]\nruns: [{world: WORLD}]\n", "give one of `worlds` (a grid), `runs` (a list)"),
    ("worlds: [nowhere.yaml]\n", "worlds: file not found:"),
    ("runs: [{world: WORLD, seed: -1}]\n", "runs[0].seed: Input should be greater than"),
    ("worlds: [WORLD]\nduration: .inf\n", "duration: Input should be a finite number"),
])
def test_bad_specs_exit_2_naming_the_key(tmp_path, capsys, text, message):
    assert main(["sweep", str(spec(tmp_path, text)), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err
    assert not (tmp_path / "out").exists()


def rows(out: Path) -> dict[str, dict[str, str]]:
    with (out / "sweep.csv").open(newline="") as fh:
        return {r["name"]: r for r in csv.DictReader(fh)}


def test_a_killed_driver_redoes_nothing_and_a_failed_run_is_recorded(tmp_path):
    (tmp_path / "broken.pt").write_text("not a policy")
    path = spec(tmp_path, "runs:\n"
                "  - {world: WORLD, seed: 0, duration: 2}\n"
                "  - {world: WORLD, seed: 1, duration: 2}\n"
                "  - {world: WORLD, seed: 2, duration: 2, policy: broken.pt}\n"
                "checks: {rsr: {min: 0.5}}\n")
    out = tmp_path / "out"
    cmd = [*SWEEP, str(path), "--out", str(out), "--cpus-per-run", "2", "--no-progress"]
    driver = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    deadline = time.time() + 600
    while time.time() < deadline and not list(out.glob("*/metrics.json")):
        time.sleep(0.5)
    driver.kill()
    driver.wait()
    first = {p.parent.name: p.stat().st_mtime_ns for p in out.glob("*/metrics.json")}
    assert first, "no run finished before the kill"
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=900)
    assert done.returncode == 1, done.stderr   # one run failed, the sweep itself finished
    assert "1 of 3 runs failed" in done.stderr
    table = rows(out)
    assert len(table) == 3
    for name, mtime in first.items():   # finished before the kill: not run again
        assert (out / name / "metrics.json").stat().st_mtime_ns == mtime
    failed = [r for r in table.values() if r["error"]]
    assert len(failed) == 1 and "broken.pt" in failed[0]["error"]
    assert all(float(r["rsr"]) >= 0.5 and not r["checks_failed"]
               for r in table.values() if not r["error"])
    summary = (out / "summary.md").read_text()
    assert "| living_room | default | 2/2 |" in summary
    assert sorted(p.name for p in (out / "plots").iterdir()) == [
        "answered_share.png", "found_share.png", "mood_positive_share.png", "rsr.png"]


def test_sigterm_stops_the_sweep_cleanly_and_a_new_start_finishes_it(tmp_path):
    path = spec(tmp_path, "worlds: [WORLD]\nseeds: [0, 1]\nduration: 120\n")
    out = tmp_path / "out"
    cmd = [*SWEEP, str(path), "--out", str(out), "--cpus-per-run", "2", "--no-progress"]
    driver = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                              text=True)
    deadline = time.time() + 600
    while time.time() < deadline and not list(out.glob("*/timeline.csv")):
        time.sleep(0.5)
    time.sleep(3)   # the run is under way
    driver.terminate()
    _, stderr = driver.communicate(timeout=300)
    assert driver.returncode == 143, stderr
    assert "Interrupted by SIGTERM" in (out / "summary.md").read_text()
    for report in out.glob("*/metrics.json"):   # whole: interrupted, or finished meanwhile
        assert json.loads(report.read_text())["duration_s"] > 0
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=900)
    assert done.returncode == 0, done.stderr
    assert all(not json.loads(p.read_text())["interrupted"] for p in out.glob("*/metrics.json"))
    assert "| living_room | default | 2/2 |" in (out / "summary.md").read_text()


@pytest.fixture(scope="module")
def ray_head() -> Iterator[str]:
    """A Ray head on loopback (2 CPUs, Ray's default token authentication), shared by the
    tests that join it; its HOST:PORT. Its own temp folder names its processes, so only
    they are stopped after (`ray stop` would also stop any other Ray on the machine)."""
    with socket.socket() as probe:   # a free port for the head's GCS
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    temp = tempfile.mkdtemp(prefix="ray", dir="/tmp")   # short: Ray's sockets live there
    env = {**os.environ, "RAY_USAGE_STATS_ENABLED": "0"}
    started = subprocess.run([RAY, "start", "--head", "--node-ip-address=127.0.0.1",
                              f"--port={port}", "--num-cpus=2", "--include-dashboard=false",
                              "--disable-usage-stats", f"--temp-dir={temp}"],
                             capture_output=True, text=True, timeout=300, env=env)
    assert started.returncode == 0, started.stderr
    yield f"127.0.0.1:{port}"
    stop_processes_naming(temp)
    shutil.rmtree(temp, ignore_errors=True)


def stop_processes_naming(text: str, wait_s: float = 30.0) -> None:
    """SIGTERM every process whose command line contains ``text``; SIGKILL what is left
    after ``wait_s``."""
    def naming() -> list[int]:
        found = []
        for proc in Path("/proc").iterdir():
            try:
                if proc.name.isdigit() and text in (proc / "cmdline").read_text():
                    found.append(int(proc.name))
            except OSError:   # gone meanwhile
                pass
        return found

    for sig in (signal.SIGTERM, signal.SIGKILL):
        for pid in naming():
            with contextlib.suppress(ProcessLookupError):
                os.kill(pid, sig)
        deadline = time.monotonic() + wait_s
        while naming() and time.monotonic() < deadline:
            time.sleep(0.5)


def test_a_sweep_joins_a_running_ray_head_by_its_address(tmp_path, ray_head):
    path = spec(tmp_path, "worlds: [WORLD]\nseeds: [4]\nduration: 2\n")
    out = tmp_path / "out"
    env = {k: v for k, v in os.environ.items() if k != "RAY_AUTH_MODE"}
    done = subprocess.run([*SWEEP, str(path), "--out", str(out), "--address", ray_head,
                           "--worker-dir", str(tmp_path / "workers"), "--no-progress"],
                          capture_output=True, text=True, timeout=900, env=env)
    assert done.returncode == 0, done.stderr
    (name,) = rows(out)
    metrics = json.loads((out / name / "metrics.json").read_text())
    assert metrics["duration_s"] == pytest.approx(2.0) and metrics["sweep_key"] in name
    events = (out / name / "events.jsonl").read_text().splitlines()
    assert json.loads(events[-1])["kind"] == "run_finished"   # collected through Ray
    assert (tmp_path / "workers" / name / "timeline.csv").exists()
    shutil.rmtree(tmp_path / "workers")


def test_dqn_trainings_over_seeds_are_summarised_against_the_rule(tmp_path, ray_head):
    config = tiny(tmp_path)
    path = tmp_path / "train.yaml"
    path.write_text(f"train_policy: {{config: {config.name}, seeds: [0, 1], episodes: 2}}\n")
    out = tmp_path / "out"
    done = subprocess.run([*SWEEP, str(path), "--out", str(out), "--address", ray_head,
                           "--no-progress"], capture_output=True, text=True, timeout=900)
    assert done.returncode == 0, done.stderr
    table = rows(out)
    assert sorted(r["seed"] for r in table.values()) == ["0", "1"]
    for r in table.values():
        assert 0 <= float(r["rsr"]) <= 1 and r["reward_margin"] and not r["error"]
        assert (out / r["name"] / "policy.pt").is_file()
    summary = (out / "summary.md").read_text()
    assert "| dqn_training | default | 2/2 |" in summary
    assert "reward margin over the rule" in summary
