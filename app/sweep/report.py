"""A sweep's report: ``sweep.csv`` (one row per run, every scalar metric), ``summary.md``
(per world and compared option, the mean and 95 % confidence interval of each headline
metric, and the runs that failed or missed a check) and ``plots/`` (one bar chart per
headline metric)."""

from __future__ import annotations

import csv
import io
import math
import statistics
from collections import defaultdict
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from scipy import stats

from app.sweep.spec import Bounds
from core.checkpoint import atomic_write, atomic_write_bytes

HOUSEHOLD = {"rsr": "RSR", "mood_positive_share": "positive mood share",
             "answered_share": "lines answered ≤ 15 s", "found_share": "find people found",
             "peak_rss_mb": "peak resident MB", "wall_s": "wall s"}
TRAINING = {"rsr": "DQN RSR", "rule_rsr": "rule RSR", "mean_reward": "DQN reward",
            "reward_margin": "reward margin over the rule", "peak_rss_mb": "peak resident MB",
            "wall_s": "wall s"}


def headline(flat: list[dict[str, Any]]) -> dict[str, str]:
    """The metrics the summary reports: a training sweep's or a household sweep's."""
    return TRAINING if any("reward_margin" in r for r in flat) else HOUSEHOLD


def _derived(m: dict[str, Any]) -> dict[str, float | None]:
    if "lines_heard" not in m:
        return {}
    heard, tries = m["lines_heard"], m["find_people_tries"]
    return {"answered_share": m["lines_answered"] / heard if heard else None,
            "found_share": m["find_people_found"] / tries if tries else None}


def flat_row(row: dict[str, Any], checks: dict[str, Bounds]) -> dict[str, Any]:
    """A CSV row: the run's entry, its scalar metrics, derived shares, checks and error."""
    run, m = row["run"], row.get("metrics") or {}
    out: dict[str, Any] = {"name": run.name, "world": Path(run.world).stem, "seed": run.seed,
                           "option": run.option(), "error": row.get("error", "")}
    if m:
        out.update({k: v for k, v in m.items() if isinstance(v, (int, float, str, bool))})
        out.update(_derived(m))
    failed = [k for k, b in checks.items() if m and not _within(m.get(k), b)]
    out["checks_failed"] = " ".join(failed)
    return out


def _within(value: Any, bounds: Bounds) -> bool:
    if not isinstance(value, (int, float)):
        return False
    return (bounds.min is None or value >= bounds.min) and (
        bounds.max is None or value <= bounds.max)


def mean_ci(values: list[float]) -> tuple[float, float]:
    """Mean and half-width of its 95 % Student-t confidence interval (0 for one value)."""
    mean = statistics.fmean(values)
    if len(values) < 2:
        return mean, 0.0
    half = stats.t.ppf(0.975, len(values) - 1) * statistics.stdev(values) / math.sqrt(
        len(values))
    return mean, float(half)


def summarise(flat: list[dict[str, Any]], metrics: dict[str, str]
              ) -> dict[tuple[str, str], dict[str, Any]]:
    """Per (world, option): runs and (mean, CI half-width) of each of ``metrics``."""
    groups: dict[tuple[str, str], list[dict[str, Any]]] = defaultdict(list)
    for r in flat:
        groups[r["world"], r["option"]].append(r)
    out = {}
    for key, rows in sorted(groups.items()):
        done = [r for r in rows if not r["error"] and "rsr" in r]
        cells = {}
        for metric in metrics:
            values = [float(r[metric]) for r in done if r.get(metric) is not None]
            cells[metric] = mean_ci(values) if values else None
        out[key] = {"runs": len(rows), "done": len(done), **cells}
    return out


def write_report(rows: list[dict[str, Any]], checks: dict[str, Bounds], out: Path,
                 interrupted: str | None = None) -> str:
    """Write sweep.csv, summary.md and plots/ into ``out``; return the summary text."""
    flat = [flat_row(r, checks) for r in rows]
    columns = list(dict.fromkeys(k for r in flat for k in r))
    text = io.StringIO()
    writer = csv.DictWriter(text, columns)
    writer.writeheader()
    writer.writerows(flat)
    atomic_write_bytes(out / "sweep.csv", text.getvalue().encode())
    metrics = headline(flat)
    summary = summarise(flat, metrics)
    md = _markdown(summary, flat, metrics, interrupted)
    atomic_write_bytes(out / "summary.md", md.encode())
    _plots(summary, metrics, out / "plots")
    return md


def _markdown(summary: dict, flat: list[dict[str, Any]], metrics: dict[str, str],
              interrupted: str | None) -> str:
    lines = ["# Sweep summary", "",
             "Mean ± half-width of the 95 % confidence interval (Student t) over seeds.", ""]
    if interrupted:
        lines += [f"**Interrupted by {interrupted}**: runs not finished are missing.", ""]
    lines += ["| world | option | runs done | " + " | ".join(metrics.values()) + " |",
              "|---|---|---|" + "---|" * len(metrics)]
    for (world, option), s in summary.items():
        cells = ["-" if s[m] is None else f"{s[m][0]:.4g} ± {s[m][1]:.3g}" for m in metrics]
        lines.append(f"| {world} | {option} | {s['done']}/{s['runs']} | " + " | ".join(cells)
                     + " |")
    bad = [r for r in flat if r["error"] or r["checks_failed"]]
    if bad:
        lines += ["", "Failed runs and missed checks:", ""]
        lines += [f"- {r['name']}: {r['error'] or 'checks failed: ' + r['checks_failed']}"
                  for r in bad]
    return "\n".join(lines) + "\n"


def _plots(summary: dict, metrics: dict[str, str], folder: Path) -> None:
    folder.mkdir(parents=True, exist_ok=True)
    labels = [f"{w}\n{o}" for w, o in summary]
    for metric in [m for m in metrics if m not in ("peak_rss_mb", "wall_s")]:
        cells = [s[metric] for s in summary.values()]
        fig, ax = plt.subplots(figsize=(max(4, 1.2 * len(labels)), 3.5))
        ax.bar(range(len(labels)), [c[0] if c else 0 for c in cells],
               yerr=[c[1] if c else 0 for c in cells], capsize=4)
        ax.set_xticks(range(len(labels)), labels, fontsize=7)
        ax.set_ylabel(metrics[metric])
        fig.tight_layout()
        atomic_write(folder / f"{metric}.png", lambda fh, f=fig: f.savefig(fh, format="png"))
        plt.close(fig)
