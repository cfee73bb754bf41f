"""Kill household runs at random moments and check what they leave behind.

    python bench/bench_kill_run.py [--kills 20] [--seed 0] [--out runs/bench-kill-run]

For each signal (SIGINT, SIGTERM, SIGKILL), ``--kills`` runs of worlds/living_room.yaml are
started and sent the signal a random 0-15 s after the run began ticking. Afterwards:
every JSONL line must parse and every timeline row have the header's width (no half-written
file), SIGINT/SIGTERM runs must exit 130/143 with their metrics.json saying so (or exit the
same way before the run began), no temporary file may be left but by SIGKILL, and the folder
must be reusable with --overwrite (its lock free, only a run's files in it). Prints one row
per signal.
"""

from __future__ import annotations

import argparse
import csv
import json
import random
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

from core.run_folder import RunFolderError, claim, release

RUN = [sys.executable, "-m", "app.cli", "run", "worlds/living_room.yaml", "--no-progress",
       "--duration", "600"]
CODES = {signal.SIGINT: 130, signal.SIGTERM: 143, signal.SIGKILL: -9}


def whole(folder: Path) -> bool:
    """Every JSONL line parses and every CSV row is complete."""
    for name in ("events.jsonl", "dialogue.jsonl"):
        path = folder / name
        if path.exists():
            try:
                [json.loads(line) for line in path.read_text().splitlines()]
            except json.JSONDecodeError:
                return False
    timeline = folder / "timeline.csv"
    if timeline.exists():
        with timeline.open(newline="") as fh:
            rows = list(csv.reader(fh))
        if rows and any(len(r) != len(rows[0]) for r in rows):
            return False
    return True


def one(folder: Path, sig: signal.Signals, delay: float) -> dict[str, object]:
    """Start a run, signal it ``delay`` s after it began ticking, and check its folder."""
    shutil.rmtree(folder, ignore_errors=True)
    proc = subprocess.Popen([*RUN, "--out", str(folder)],
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    while not (folder / "timeline.csv").exists() and proc.poll() is None:
        time.sleep(0.1)
    time.sleep(delay)
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=300)
    started = (folder / "timeline.csv").exists()
    metrics = folder / "metrics.json"
    reported = (sig == signal.SIGKILL or not started
                or json.loads(metrics.read_text()).get("interrupted_by") == sig.name)
    temp = [p.name for p in folder.rglob("*.tmp")]
    try:   # what `--overwrite` does first: the lock is free and only run files are there
        claim(folder, overwrite=True)
        release(folder)
        reusable = True
    except RunFolderError:
        reusable = False
    return {"code_ok": proc.returncode == CODES[sig], "whole": whole(folder),
            "reported": reported, "temp": temp, "traceback": "Traceback" in err,
            "reusable": reusable, "started": started}


def main() -> None:
    """Run the kills and print the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--kills", type=int, default=20)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--out", type=Path, default=Path("runs/bench-kill-run"))
    args = parser.parse_args()
    rng = random.Random(args.seed)
    print("| signal | kills | killed mid-run | exit code as documented | files whole | "
          "report says so | temp files left | tracebacks | folder reusable |")
    print("|---|---|---|---|---|---|---|---|---|")
    for sig in CODES:
        rows = [one(args.out / f"{sig.name}-{i}", sig, rng.uniform(0.0, 15.0))
                for i in range(args.kills)]
        count = {k: sum(bool(r[k]) for r in rows) for k in
                 ("started", "code_ok", "whole", "reported", "temp", "traceback", "reusable")}
        print(f"| {sig.name} | {len(rows)} | {count['started']} | {count['code_ok']} | "
              f"{count['whole']} | {count['reported']} | {count['temp']} | "
              f"{count['traceback']} | {count['reusable']} |", flush=True)


if __name__ == "__main__":
    main()
