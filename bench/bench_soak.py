"""The soak report: RSR and memory per simulated hour of a long looping run, and each
injected fault with its recovery.

    companion run worlds/nursing_home.yaml --loop --duration 28800 --out runs/soak-8h
    companion run worlds/nursing_home.yaml --loop --duration 28800 \\
        --faults worlds/faults/soak_8h.yaml --out runs/soak-8h-faults
    python bench/bench_soak.py runs/soak-8h runs/soak-8h-faults

Memory comes from the run's ``resources`` events (resident MB every 300 simulated s);
"growth" compares the peak of the last hour with that of the first.
"""

from __future__ import annotations

import argparse
import csv
import json
from pathlib import Path

HOUR = 3600.0


def hourly(folder: Path) -> list[dict[str, float]]:
    """Per simulated hour: RSR (share of secure homeostasis steps) and peak resident MB."""
    with (folder / "timeline.csv").open(newline="") as fh:
        rows = [(float(r["t"]), r["secure"] == "1") for r in csv.DictReader(fh)]
    events = [json.loads(line) for line in (folder / "events.jsonl").read_text().splitlines()]
    memory = [(e["t"], e["rss_mb"]) for e in events if e["kind"] == "resources"]
    out = []
    for h in range(int(max(t for t, _ in rows) // HOUR) + 1):
        secure = [s for t, s in rows if h * HOUR < t <= (h + 1) * HOUR]
        rss = [m for t, m in memory if h * HOUR <= t < (h + 1) * HOUR]
        if secure:
            out.append({"hour": h + 1, "rsr": sum(secure) / len(secure),
                        "rss_peak_mb": max(rss) if rss else float("nan")})
    return out


def report(folder: Path) -> str:
    """The Markdown table of one soak run."""
    metrics = json.loads((folder / "metrics.json").read_text())
    hours = hourly(folder)
    lines = [f"**{folder.name}** ({metrics['duration_s']:.0f} simulated s, "
             f"{metrics['wall_s']:.0f} s wall, interrupted: {metrics['interrupted']})", "",
             "| hour | RSR % | peak resident MB |", "|---|---|---|"]
    lines += [f"| {h['hour']} | {100 * h['rsr']:.2f} | {h['rss_peak_mb']:.0f} |" for h in hours]
    first, last = hours[0]["rss_peak_mb"], hours[-1]["rss_peak_mb"]
    lines += ["", f"RSR over the run {100 * metrics['rsr']:.2f} %; memory hour "
              f"{hours[-1]['hour']} vs hour 1: {100 * (last - first) / first:+.1f} %."]
    faults = metrics.get("faults") or []
    if faults:
        recovered = [f for f in faults if f["recovery"] is not None]
        lines += [f"Faults injected {len(faults)}, followed by their recovery event "
                  f"{len(recovered)}:", "", "| t s | fault | recovery | after s |",
                  "|---|---|---|---|"]
        lines += [f"| {f['t']:.0f} | {f['fault']} | {f['recovery'] or 'NONE'} | "
                  + (f"{f['recovery_t'] - f['t']:.1f} |" if f["recovery"] else "- |")
                  for f in faults]
    return "\n".join(lines)


def main() -> None:
    """Print the report of each run folder given."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folders", type=Path, nargs="+")
    for folder in parser.parse_args().folders:
        print(report(folder) + "\n")


if __name__ == "__main__":
    main()
