"""Run folders are claimed, never mixed, and keep whole files through interruptions:
real `companion run` processes stopped by SIGINT, SIGTERM and SIGKILL, two runs into one
folder, and a file-size limit standing in for a full disk."""

from __future__ import annotations

import csv
import json
import os
import resource
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from core.run_folder import RunFolderError, claim, default_folder, release

RUN = [sys.executable, "-m", "app.cli", "run", "worlds/living_room.yaml", "--no-progress"]


def ctrl_c_as_at_a_terminal() -> None:
    """In the child: SIGINT as a terminal delivers it (a shell's background job inherits
    it ignored, and Python then leaves it ignored)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def start(out: Path, *extra: str) -> subprocess.Popen:
    return subprocess.Popen([*RUN, "--out", str(out), *extra], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True,
                            preexec_fn=ctrl_c_as_at_a_terminal)


def wait_running(out: Path, proc: subprocess.Popen, seconds: float = 2.0) -> None:
    """Wait until the run has ticked ``seconds`` of simulated time."""
    deadline = time.time() + 120
    while time.time() < deadline and proc.poll() is None:
        timeline = out / "timeline.csv"
        if timeline.exists() and len(timeline.read_text().splitlines()) > 1 + seconds * 10:
            return
        time.sleep(0.2)
    raise AssertionError(f"the run did not start: {proc.poll()}")


def assert_whole(out: Path) -> list[dict]:
    """Every JSONL line parses and every timeline row has the header's width."""
    events = [json.loads(line) for line in (out / "events.jsonl").read_text().splitlines()]
    with (out / "timeline.csv").open(newline="") as fh:
        rows = list(csv.reader(fh))
    assert rows and all(len(r) == len(rows[0]) for r in rows)
    for name in ("dialogue.jsonl", "view/trees.jsonl"):
        for line in (out / name).read_text().splitlines() if (out / name).exists() else []:
            json.loads(line)
    return events


@pytest.mark.parametrize(("sig", "code", "name"), [(signal.SIGTERM, 143, "SIGTERM"),
                                                   (signal.SIGINT, 130, "SIGINT")])
def test_a_stopped_run_writes_its_report_and_exits_with_the_signal(tmp_path, sig, code, name):
    out = tmp_path / "run"
    proc = start(out, "--duration", "600")
    wait_running(out, proc)
    proc.send_signal(sig)
    stdout, stderr = proc.communicate(timeout=120)
    assert proc.returncode == code, stderr
    assert f"INTERRUPTED by {name}" in stdout and "Traceback" not in stderr
    metrics = json.loads((out / "metrics.json").read_text())
    assert metrics["interrupted"] and metrics["interrupted_by"] == name
    assert 0 < metrics["duration_s"] < 600
    kinds = [e["kind"] for e in assert_whole(out)]
    assert kinds[-2:] == ["interrupted", "run_finished"]
    assert sorted(p.name for p in (out / "plots").iterdir()) == [
        "actions.png", "mood.png", "motivations.png"]
    assert not list(out.rglob("*.tmp")) and not (out / ".lock").exists()


def children(pid: int) -> set[int]:
    """The processes whose parent is ``pid`` (from /proc)."""
    found = set()
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[1]) == pid:
            found.add(int(stat.parent.name))
    return found


def gone(pids: set[int], seconds: float) -> bool:
    """Whether every process in ``pids`` has ended within ``seconds``."""
    deadline = time.time() + seconds
    while time.time() < deadline:
        if not any(Path(f"/proc/{pid}").exists() for pid in pids):
            return True
        time.sleep(0.2)
    return False


def test_a_killed_run_leaves_whole_lines_and_its_folder_can_be_reused(tmp_path):
    out = tmp_path / "run"
    proc = start(out, "--duration", "600")
    wait_running(out, proc, seconds=5)
    helpers = children(proc.pid)   # the camera's helper (two cores) and Python's tracker
    assert helpers or (os.cpu_count() or 1) < 2
    proc.kill()
    proc.wait(timeout=60)
    assert gone(helpers, 20), "a helper process outlived the killed run"
    assert_whole(out)
    again = subprocess.run([*RUN, "--out", str(out), "--duration", "1"], capture_output=True,
                           text=True, timeout=300)
    assert again.returncode == 2 and "holds an earlier run: pass --overwrite" in again.stderr
    again = subprocess.run([*RUN, "--out", str(out), "--duration", "1", "--overwrite"],
                           capture_output=True, text=True, timeout=300)
    assert again.returncode == 0, again.stderr
    events = assert_whole(out)
    assert [e["kind"] for e in events].count("run_started") == 1 and events[-1]["t"] <= 1.0


def test_a_second_run_into_a_busy_folder_is_refused(tmp_path):
    out = tmp_path / "run"
    first = start(out, "--duration", "600")
    try:
        wait_running(out, first)
        second = subprocess.run([*RUN, "--out", str(out), "--duration", "1", "--overwrite"],
                                capture_output=True, text=True, timeout=300)
        assert second.returncode == 2
        assert f"process {first.pid} is running into this folder" in second.stderr
    finally:
        first.terminate()
        first.communicate(timeout=120)
    assert first.returncode == 143
    assert_whole(out)


def test_a_full_disk_stops_the_run_with_whole_files(tmp_path):
    """RLIMIT_FSIZE makes writes past 20 kB fail (EFBIG) as a full disk would."""
    out = tmp_path / "run"

    def small_files() -> None:
        resource.setrlimit(resource.RLIMIT_FSIZE, (20_000, 20_000))

    done = subprocess.run([*RUN, "--out", str(out), "--duration", "600"], capture_output=True,
                          text=True, timeout=300, preexec_fn=small_files)
    assert done.returncode == 2 and "Traceback" not in done.stderr
    assert "writing the run failed (File too large)" in done.stderr
    assert_whole(out)
    assert all(p.stat().st_size < 20_000 for p in out.rglob("*") if p.is_file())


def test_claim_refuses_folders_it_must_not_clear(tmp_path):
    foreign = tmp_path / "thesis"
    foreign.mkdir()
    (foreign / "chapter1.tex").write_text("precious")
    for overwrite in (False, True):
        with pytest.raises(RunFolderError, match="not empty and holds no run"):
            claim(foreign, overwrite)
    assert sorted(p.name for p in foreign.iterdir()) == ["chapter1.tex"]
    mixed = tmp_path / "mixed"
    mixed.mkdir()
    (mixed / "metrics.json").write_text("{}")
    (mixed / "notes.txt").write_text("mine")
    with pytest.raises(RunFolderError, match=r"also holds notes\.txt"):
        claim(mixed, overwrite=True)
    with pytest.raises(RunFolderError, match="cannot create the run folder"):
        claim(foreign / "chapter1.tex" / "run")
    with pytest.raises(RunFolderError, match="cannot create the run folder"):
        claim(Path("/proc/companion-run"))


def test_overwrite_clears_only_the_earlier_run(tmp_path):
    out = tmp_path / "run"
    (out / "frames").mkdir(parents=True)
    (out / "frames" / "0001-t0000.0-stand_by.png").write_bytes(b"old")
    (out / "events.jsonl").write_text("{}\n")
    (out / "map_kitchen.png").write_bytes(b"old")
    claim(out, overwrite=True)
    try:
        assert [p.name for p in out.iterdir()] == [".lock"]
        assert (out / ".lock").read_text().strip() == str(os.getpid())
    finally:
        release(out)
    assert not (out / ".lock").exists()


def test_default_folders_are_new_each_time(tmp_path):
    first = default_folder(tmp_path, "living_room")
    first.mkdir()
    second = default_folder(tmp_path, "living_room")
    assert first != second and first.name.startswith("living_room-")
