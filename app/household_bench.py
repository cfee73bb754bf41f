"""``companion bench household``: the whole robot in every shipped world, over seeds.

Each world runs for its own duration, and the nursing home also for a long afternoon
(``long_s``, an hour by default), once per seed; every run is a ``companion run`` in its own
process (its peak memory is its own) writing a run folder under ``out``. A run whose
``metrics.json`` is already there and complete is not run again, so an interrupted bench
resumes where it stopped. The summary gives, per world and duration, the mean and range
of each interaction metric, and over all runs the share of lines answered within 15 s
and the median time to an answer; ``--docs`` writes the table into docs/BENCHMARKS.md
between two markers.
"""

from __future__ import annotations

import json
import statistics
import subprocess
import sys
from collections.abc import Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from app.report import ANSWERED_WITHIN_S, answer_latencies
from core.checkpoint import atomic_write_bytes
from core.errors import UserError
from core.paths import WORLDS_DIR

WORLDS = ("living_room", "nursing_home", "birthday_party", "low_battery_night",
          "care_home_evening", "two_rooms", "day_room_morning")
LONG_WORLD = "nursing_home"
METRICS = ("rsr", "mood_positive_share", "lines_said", "lines_answered",
           "answer_latency_s_median", "lines_responded", "lines_answered_at_all",
           "lines_ignored", "voices_not_made_out", "voices_approached", "dont_know_answers",
           "find_people_tries", "find_people_found", "questions_asked", "questions_grounded",
           "companion_replies", "care_alerts", "wall_s", "peak_rss_mb")
BEGIN, END = "<!-- bench household: begin -->", "<!-- bench household: end -->"


@dataclass(frozen=True)
class BenchRun:
    """One run of the bench: a world, its duration (None: the scenario's own) and a seed."""

    world: str
    duration: float | None
    seed: int

    @property
    def config(self) -> str:
        """The world and duration, as the table's row name."""
        return self.world if self.duration is None else f"{self.world} {self.duration:.0f} s"

    @property
    def folder(self) -> str:
        """The run folder's name."""
        length = "" if self.duration is None else f"-{self.duration:.0f}s"
        return f"{self.world}{length}-seed{self.seed}"


def plan(worlds: Sequence[str], seeds: Sequence[int], long_s: float | None) -> list[BenchRun]:
    """Every world at its own duration, then the long nursing-home afternoon, per seed."""
    unknown = [w for w in worlds if not (WORLDS_DIR / f"{w}.yaml").is_file()]
    if unknown:
        raise UserError(f"no such world: {', '.join(unknown)} (see {WORLDS_DIR})")
    runs = [BenchRun(w, None, s) for w in worlds for s in seeds]
    if long_s and LONG_WORLD in worlds:
        runs += [BenchRun(LONG_WORLD, long_s, s) for s in seeds]
    return runs


def _complete(folder: Path) -> dict[str, Any] | None:
    path = folder / "metrics.json"
    if not path.is_file():
        return None
    metrics = json.loads(path.read_text())
    return None if metrics.get("interrupted") else metrics


def run_one(run: BenchRun, out: Path) -> dict[str, Any]:
    """The metrics of ``run`` (run now in a child process unless already complete), with
    the answer latencies of its lines."""
    folder = out / run.folder
    metrics = _complete(folder)
    if metrics is None:
        cmd = [sys.executable, "-m", "app.cli", "run", str(WORLDS_DIR / f"{run.world}.yaml"),
               "--out", str(folder), "--overwrite", "--seed", str(run.seed), "--no-progress",
               "--json"]
        if run.duration is not None:
            cmd += ["--duration", str(run.duration)]
        done = subprocess.run(cmd, capture_output=True, text=True)
        metrics = _complete(folder)
        if done.returncode != 0 or metrics is None:
            raise UserError(f"{run.folder} failed (exit {done.returncode}):\n{done.stderr}")
    events = [json.loads(line) for line in (folder / "events.jsonl").read_text().splitlines()]
    return {"config": run.config, "world": run.world, "seed": run.seed,
            **{k: metrics[k] for k in METRICS}, "latencies": answer_latencies(events)}


def summarise(rows: list[dict[str, Any]]) -> dict[str, Any]:
    """Mean and range per metric for each world and duration; pooled answer figures."""
    configs: dict[str, dict[str, Any]] = {}
    for config in dict.fromkeys(r["config"] for r in rows):
        mine = [r for r in rows if r["config"] == config]
        stats = {}
        for key in METRICS:
            values = [r[key] for r in mine if r[key] is not None]
            stats[key] = ({"mean": statistics.fmean(values), "min": min(values),
                           "max": max(values)} if values else None)
        configs[config] = {"runs": len(mine), **stats}
    latencies = sorted(x for r in rows for x in r["latencies"])
    said = sum(r["lines_said"] for r in rows)   # to the robot: not encouragement, not others
    tries = sum(r["find_people_tries"] for r in rows)
    asked = sum(r["questions_asked"] for r in rows)
    return {
        "configs": configs,
        "lines_said": said,
        "lines_answered_share": sum(x <= ANSWERED_WITHIN_S for x in latencies) / said
        if said else None,
        "answer_latency_s_median": statistics.median(latencies) if latencies else None,
        **{f"{key}_share": sum(r[key] for r in rows) / said if said else None
           for key in ("lines_responded", "lines_answered_at_all")},
        "lines_ignored": sum(r["lines_ignored"] for r in rows),
        "find_people_found_share": sum(r["find_people_found"] for r in rows) / tries
        if tries else None,
        "questions_grounded_share": sum(r["questions_grounded"] for r in rows) / asked
        if asked else None,
        "rsr_min": min(r["rsr"] for r in rows),
    }


def _cell(stat: dict[str, float] | None, digits: int, scale: float = 1.0) -> str:
    if stat is None:
        return "-"
    mean, lo, hi = (stat[k] * scale for k in ("mean", "min", "max"))
    if lo == hi:
        return f"{mean:.{digits}f}"
    return f"{mean:.{digits}f} ({lo:.{digits}f}-{hi:.{digits}f})"


def table(summary: dict[str, Any], seeds: Sequence[int]) -> str:
    """The summary as a Markdown table (mean, and range over the seeds in brackets)."""
    cols = [("RSR %", "rsr", 2, 100), ("positive mood %", "mood_positive_share", 0, 100),
            ("lines said to it", "lines_said", 1, 1), ("answered ≤ 15 s", "lines_answered", 1, 1),
            ("median answer s", "answer_latency_s_median", 1, 1),
            ("responded ≤ 15 s", "lines_responded", 1, 1),
            ("answered at all", "lines_answered_at_all", 1, 1),
            ("ignored", "lines_ignored", 1, 1), ("went over", "voices_approached", 1, 1),
            ("don't know", "dont_know_answers", 1, 1),
            ("find people tries", "find_people_tries", 1, 1),
            ("found", "find_people_found", 1, 1), ("questions", "questions_asked", 1, 1),
            ("grounded", "questions_grounded", 1, 1),
            ("own replies", "companion_replies", 1, 1), ("care alerts", "care_alerts", 1, 1),
            ("wall s", "wall_s", 0, 1),
            ("peak MB", "peak_rss_mb", 0, 1)]
    lines = ["| world | " + " | ".join(c[0] for c in cols) + " |",
             "| --- |" + " --- |" * len(cols)]
    for config, stats in summary["configs"].items():
        cells = [_cell(stats[key], digits, scale) for _, key, digits, scale in cols]
        lines.append(f"| {config} | " + " | ".join(cells) + " |")

    def share(key: str) -> str:
        value = summary[key]
        return "-" if value is None else f"{100 * value:.1f} %"

    latency = summary["answer_latency_s_median"]
    lines += ["", f"Over all {sum(c['runs'] for c in summary['configs'].values())} runs "
              f"(seeds {', '.join(map(str, seeds))}): lines answered within 15 s "
              f"{share('lines_answered_share')} of {summary['lines_said']}, median answer "
              f"{'-' if latency is None else f'{latency:.1f} s'}; responded to within 15 s "
              f"{share('lines_responded_share')}, answered at all (after at most one "
              f"repeat) {share('lines_answered_at_all_share')}, ignored "
              f"{summary['lines_ignored']}; find people "
              f"{share('find_people_found_share')} of tries; questions grounded "
              f"{share('questions_grounded_share')}; lowest RSR {100 * summary['rsr_min']:.2f} %."]
    return "\n".join(lines)


def write_docs(text: str, path: Path, command: str) -> None:
    """Put ``text`` (with the command that made it) between the markers in ``path``."""
    doc = path.read_text(encoding="utf-8")
    block = f"{BEGIN}\n`{command}`\n\n{text}\n{END}"
    if BEGIN in doc and END in doc:
        doc = doc[:doc.index(BEGIN)] + block + doc[doc.index(END) + len(END):]
    else:
        doc = doc.rstrip("\n") + "\n\n## The whole robot in the household\n\n" + block + "\n"
    atomic_write_bytes(path, doc.encode("utf-8"))


def bench(runs: list[BenchRun], out: Path, jobs: int = 1) -> list[dict[str, Any]]:
    """Run (or reuse) every run, ``jobs`` at a time; their rows in plan order."""
    out.mkdir(parents=True, exist_ok=True)
    with ThreadPoolExecutor(max_workers=jobs) as pool:
        return list(pool.map(lambda r: run_one(r, out), runs))
