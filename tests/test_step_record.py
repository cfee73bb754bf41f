"""A run's homeostasis steps: running totals equal the whole series, the rows are handed
to the timeline once each, and the plots come from the timeline on disk."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from app.report import TimelineWriter, compute_metrics, plot_run, read_timeline
from behaviours.step_record import StepRecord
from mind.personality import ACTIONS, DRIVES, MOTIVATIONS, STIMULI


def _rows(n: int, seed: int = 0) -> list[dict]:
    rng = np.random.default_rng(seed)
    return [{"t": float(i + 1), "action": ACTIONS[rng.integers(len(ACTIONS))],
             "relieving": bool(rng.integers(2)), "drives": rng.random(len(DRIVES)),
             "motivations": rng.random(len(MOTIVATIONS)),
             "stimuli": rng.integers(0, 2, len(STIMULI)).astype(bool),
             "mood": float(rng.random()), "mood_positive": bool(rng.integers(2)),
             "secure": bool(rng.random() < 0.9)} for i in range(n)]


def test_totals_match_the_whole_series_and_rows_are_taken_once() -> None:
    rows, record = _rows(500), StepRecord()
    taken = []
    for i, row in enumerate(rows):
        record.append(row)
        if i % 7 == 0:
            taken += record.take()
    taken += record.take()
    assert taken == rows and record.take() == []
    metrics = compute_metrics(record, [])
    assert metrics["homeostasis_steps"] == 500
    assert metrics["rsr"] == np.mean([r["secure"] for r in rows])
    assert metrics["mood_positive_share"] == np.mean([r["mood_positive"] for r in rows])
    assert metrics["action_seconds"] == {a: sum(r["action"] == a for r in rows) for a in ACTIONS}
    highest = np.max([r["drives"] for r in rows], axis=0).round(4)
    assert list(metrics["max_drive"].values()) == highest.tolist()
    assert record.last_action == rows[-1]["action"]


def test_an_empty_run_has_no_rates() -> None:
    metrics = compute_metrics(StepRecord(), [])
    assert metrics["rsr"] is None and metrics["max_drive"] == {}
    assert StepRecord().last_action is None


def test_plots_are_drawn_from_the_timeline_on_disk(tmp_path: Path) -> None:
    rows, writer = _rows(60), TimelineWriter(tmp_path / "timeline.csv")
    writer.write(rows[:25])
    writer.write(rows[25:])
    writer.close()
    series = read_timeline(tmp_path / "timeline.csv")
    assert series["t"].tolist() == [r["t"] for r in rows]
    assert series["action"].tolist() == [r["action"] for r in rows]
    assert np.allclose(series[f"m_{MOTIVATIONS[2]}"], [r["motivations"][2] for r in rows],
                       atol=1e-5)
    lower, upper = np.zeros(len(MOTIVATIONS)), np.ones(len(MOTIVATIONS))
    paths = plot_run(tmp_path / "timeline.csv", lower, upper, 0.5, tmp_path / "plots")
    assert [p.name for p in paths] == ["motivations.png", "actions.png", "mood.png"]
    assert all(p.stat().st_size > 1000 for p in paths)
