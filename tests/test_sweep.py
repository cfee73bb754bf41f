"""`companion sweep` on a real local Ray: runs spread as tasks, a failed run is recorded
while the others finish, a killed driver loses and redoes nothing, and a sweep joins a Ray
head started on loopback with `ray start --head`."""

from __future__ import annotations

import csv
import json
import os
import shutil
import subprocess
import sys
import time
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


@pytest.fixture(scope="module")
def ray_head():
    """A Ray head on loopback (2 CPUs), shared by the tests that join it, stopped after."""
    env = {**os.environ, "RAY_USAGE_STATS_ENABLED": "0"}
    started = subprocess.run([RAY, "start", "--head", "--node-ip-address=127.0.0.1",
                              "--port=0", "--num-cpus=2", "--include-dashboard=false",
                              "--disable-usage-stats"], capture_output=True, text=True,
                             timeout=300, env=env)
    assert started.returncode == 0, started.stderr
    yield
    subprocess.run([RAY, "stop", "--force"], capture_output=True, timeout=300)


def test_a_sweep_joins_a_running_ray_head(tmp_path, ray_head):
    path = spec(tmp_path, "worlds: [WORLD]\nseeds: [4]\nduration: 2\n")
    out = tmp_path / "out"
    done = subprocess.run([*SWEEP, str(path), "--out", str(out), "--address", "auto",
                           "--worker-dir", str(tmp_path / "workers"), "--no-progress"],
                          capture_output=True, text=True, timeout=900)
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
    done = subprocess.run([*SWEEP, str(path), "--out", str(out), "--address", "auto",
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
