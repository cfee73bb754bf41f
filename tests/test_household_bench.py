"""`companion bench household`: the plan of runs, resuming from complete run folders, the
summary over seeds and the table written into the benchmarks page."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from app.cli import main
from app.household_bench import BEGIN, END, METRICS, bench, plan, summarise, table, write_docs
from core.errors import UserError


def fake_run(folder: Path, seed: int, latencies: list[float]) -> None:
    """A complete run folder: metrics and the heard/say events behind the latencies."""
    folder.mkdir(parents=True)
    metrics = dict.fromkeys(METRICS, 1)
    metrics.update(rsr=1.0 - seed / 100, interrupted=False, lines_said=len(latencies) + 1,
                   answer_latency_s_median=None, find_people_tries=4, find_people_found=seed,
                   questions_asked=2, questions_grounded=1)
    (folder / "metrics.json").write_text(json.dumps(metrics))
    events = []
    for i, lag in enumerate([*latencies, None], start=1):
        events.append({"t": 10.0 * i, "kind": "heard", "line": i})
        if lag is not None:
            events.append({"t": 10.0 * i + lag, "kind": "say", "line": i})
    (folder / "events.jsonl").write_text("\n".join(json.dumps(e) for e in events) + "\n")


def test_plan_has_each_world_per_seed_and_the_long_afternoon():
    runs = plan(["living_room", "nursing_home"], [0, 1], 3600)
    assert [r.folder for r in runs] == [
        "living_room-seed0", "living_room-seed1", "nursing_home-seed0", "nursing_home-seed1",
        "nursing_home-3600s-seed0", "nursing_home-3600s-seed1"]
    assert runs[-1].config == "nursing_home 3600 s"
    with pytest.raises(UserError, match="no such world"):
        plan(["atlantis"], [0], 0)


def test_complete_runs_are_reused_and_summarised(tmp_path):
    fake_run(tmp_path / "living_room-seed0", 0, [0.5, 2.0])
    fake_run(tmp_path / "living_room-seed1", 1, [20.0])
    rows = bench(plan(["living_room"], [0, 1], 0), tmp_path)   # nothing runs
    summary = summarise(rows)
    assert summary["lines_said"] == 5
    assert summary["lines_answered_share"] == pytest.approx(2 / 5)   # 20 s is too late
    assert summary["answer_latency_s_median"] == 2.0
    assert summary["find_people_found_share"] == pytest.approx(1 / 8)
    assert summary["configs"]["living_room"]["rsr"] == {"mean": 0.995, "min": 0.99, "max": 1.0}
    text = table(summary, [0, 1])
    assert "| living_room | 99.50 (99.00-100.00) |" in text and "40.0 % of 5" in text


def test_the_table_goes_between_the_markers(tmp_path):
    doc = tmp_path / "BENCHMARKS.md"
    doc.write_text("# Benchmarks\n")
    write_docs("first", doc, "companion bench household")
    write_docs("second", doc, "companion bench household --seeds 0")
    text = doc.read_text()
    assert text.count(BEGIN) == 1 and text.count(END) == 1 and "first" not in text
    assert "`companion bench household --seeds 0`\n\nsecond" in text


def test_an_unknown_world_exits_2(capsys):
    assert main(["bench", "household", "--worlds", "atlantis"]) == 2
    assert "no such world" in capsys.readouterr().err
