"""The run profile counts each part's own time once, and a profiled run reports its parts."""

from __future__ import annotations

import json
import subprocess
import sys
import time

from core.profiling import Profile, profile_table


class Worker:
    def __init__(self, inner: Worker | None = None) -> None:
        self.inner = inner

    def work(self, seconds: float) -> str:
        time.sleep(seconds)
        if self.inner is not None:
            self.inner.work(seconds)
        return "done"


def test_a_timed_call_inside_another_is_taken_out_of_the_outer_part() -> None:
    profile = Profile()
    inner, outer = Worker(), Worker()
    outer.inner = inner
    profile.wrap(inner, "work", "inner")
    profile.wrap(outer, "work", "outer")
    assert outer.work(0.05) == "done"
    assert 0.045 <= profile.seconds["inner"] < 0.09
    assert 0.045 <= profile.seconds["outer"] < 0.09   # its own sleep only
    assert profile.calls == {"inner": 1, "outer": 1}
    report = profile.report(0.2)
    assert list(report["parts"])[-1] == "other" or report["parts"]["other"]["seconds"] > 0
    assert abs(sum(r["seconds"] for r in report["parts"].values()) - 0.2) < 0.02


def test_only_the_wrapped_object_is_timed_and_none_is_skipped() -> None:
    profile = Profile()
    timed, plain = Worker(), Worker()
    profile.wrap(timed, "work", "work")
    profile.wrap(None, "work", "nothing")
    plain.work(0.0)
    assert profile.calls["work"] == 0
    timed.work(0.0)
    assert profile.calls["work"] == 1
    assert "nothing" not in profile.seconds


def test_an_exception_is_still_counted_and_raised() -> None:
    profile = Profile()

    def fail() -> None:
        raise ValueError("boom")

    timed = profile.timed(fail, "fail")
    try:
        timed()
    except ValueError:
        pass
    else:
        raise AssertionError("the exception was swallowed")
    assert profile.calls["fail"] == 1


def test_the_table_lists_every_part_with_its_share() -> None:
    profile = Profile()
    profile.add("start-up", 1.0)
    profile.add("render", 3.0)
    profile.calls["render"] = 300
    text = profile_table(profile.report(5.0))
    assert "| render | 3.0 | 60.0 % | 300 | 10.00 |" in text
    assert "| other | 1.0 | 20.0 % | 0 |  |" in text
    assert text.endswith("| **total** | 5.0 | 100 % | | |")


def test_a_profiled_run_reports_where_its_time_went(tmp_path) -> None:
    out = tmp_path / "run"
    done = subprocess.run([sys.executable, "-m", "app.cli", "run", "worlds/living_room.yaml",
                           "--duration", "20", "--no-progress", "--profile", "--out", str(out)],
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    profile = json.loads((out / "metrics.json").read_text())["profile"]
    parts = profile["parts"]
    assert parts["simulation step"]["calls"] == 200   # one per 0.1-s step
    assert parts["tree"]["calls"] == 200
    assert parts["render"]["calls"] >= 20 and parts["detect"]["calls"] >= 20
    assert parts["start-up"]["seconds"] > 0
    assert abs(sum(p["seconds"] for p in parts.values()) - profile["wall_s"]) < 0.05
    assert "| render |" in done.stdout and "| **total** |" in done.stdout
