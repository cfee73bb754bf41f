"""The tablet's commands as a person runs them: `companion view` and `companion tablet`
print where they serve (with a token off loopback) and stop on a signal; bad use exits 2."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import urllib.request
from pathlib import Path

from test_run_folder import ctrl_c_as_at_a_terminal

from app.report import TIMELINE_COLUMNS

ROOT = Path(__file__).resolve().parents[1]
COMPANION = [sys.executable, "-m", "app.cli"]
ENV = {**os.environ, "PYTHONPATH": str(ROOT)}


def small_run(folder: Path) -> Path:
    """A run folder with two timeline rows and one event."""
    folder.mkdir()
    row = {c: "0" for c in TIMELINE_COLUMNS} | {"action": "stand_by", "mood_positive": "1"}
    lines = [",".join(TIMELINE_COLUMNS)] + [",".join({**row, "t": t}[c] for c in
                                                      TIMELINE_COLUMNS) for t in ("1.0", "2.0")]
    (folder / "timeline.csv").write_text("\n".join(lines) + "\n")
    (folder / "events.jsonl").write_text(json.dumps(
        {"t": 0.0, "kind": "action", "action": "stand_by", "reason": "policy"}) + "\n")
    return folder


def serve(args: list[str]) -> tuple[subprocess.Popen, str, str]:
    """Start a serving command; the process, its address and its token line (if any)."""
    proc = subprocess.Popen([*COMPANION, *args, "--port", "0"], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=ENV,
                            preexec_fn=ctrl_c_as_at_a_terminal)
    url = proc.stdout.readline().split(": ", 1)[1].strip()
    token = proc.stdout.readline() if "token=" in url else ""
    return proc, url, token


def test_view_serves_a_run_folder_and_stops_on_sigint(tmp_path):
    proc, url, _ = serve(["view", str(small_run(tmp_path / "run"))])
    try:
        assert url.startswith("http://127.0.0.1:")
        index = json.load(urllib.request.urlopen(url + "api/replay", timeout=30))
        assert index["duration"] == 2.0 and index["rows"] == 2
        at = json.load(urllib.request.urlopen(url + "api/replay/at?t=1.5", timeout=30))
        assert at["action"] == "stand_by" and at["why"]["reason"] == "policy"
    finally:
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=60)   # drains the pipes: a full one would block it
        assert proc.returncode == 0, err


def test_off_loopback_a_token_is_printed_and_needed(tmp_path):
    proc, url, token = serve(["view", str(small_run(tmp_path / "run")), "--host", "0.0.0.0"])
    try:
        secret = url.split("token=")[1]
        assert secret in token
        base = url.split("?")[0].replace("0.0.0.0", "127.0.0.1")
        try:
            urllib.request.urlopen(base + "api/config", timeout=30)
            raise AssertionError("served without the token")
        except urllib.error.HTTPError as exc:
            assert exc.code == 401
        ok = urllib.request.urlopen(base + "api/config?token=" + secret, timeout=30)
        assert json.load(ok)["kind"] == "replay"
    finally:
        proc.send_signal(signal.SIGTERM)
        _, err = proc.communicate(timeout=60)
        assert proc.returncode == 143, err


def test_bad_use_exits_2(tmp_path):
    for args in (["view", str(tmp_path)],                                  # not a run folder
                 ["run", "worlds/living_room.yaml", "--port", "9999"],     # --port needs --tablet
                 ["view", str(small_run(tmp_path / "r")), "--port", "70000"]):
        done = subprocess.run([*COMPANION, *args], capture_output=True, text=True, env=ENV,
                              timeout=120)
        assert done.returncode == 2 and "Traceback" not in done.stderr, (args, done.stderr)
