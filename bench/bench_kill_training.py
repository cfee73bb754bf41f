"""Interruptions of a training: kill a tiny `companion train policy` at random times with
SIGINT, SIGTERM and SIGKILL, resume each run with `--resume` (its own configuration), and
check what it left: the exit codes, that every CSV row parses, that no row is there twice,
that the logs equal those of an uninterrupted run (all but the wall times), that no
temporary file (`.*.tmp`) is left, and that the resumed run finished.

Each kill lands at a time drawn uniformly over the training's own span (from the moment the
run's configuration is written until the uninterrupted reference run ended), so some land
in the set-up, most in the loop, a few in the final validation; those that land after
`summary.json` is written (the plots, the interpreter's exit) are counted apart.

Usage: python bench/bench_kill_training.py [--n 20] [--out runs/bench-kill-training] [--seed 0]
"""

from __future__ import annotations

import argparse
import collections
import csv
import json
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
TOTAL = 600  # decisions the tiny training collects
CONFIG = f"""env: {{episode_steps: 200}}
network: {{hidden: [32, 32], head: 16}}
train: {{num_envs: 4, episode_steps: 200, total_transitions: {TOTAL}, learning_starts: 50,
        buffer_size: 2000, eval_episodes: 1, eval_every: 50, checkpoint_every: 20}}
"""
LOGS = {"train_log.csv": 3, "eval_log.csv": 2}  # how many leading columns key a row
KINDS = {"SIGINT": signal.SIGINT, "SIGTERM": signal.SIGTERM, "SIGKILL": signal.SIGKILL}


def companion(*args: str) -> subprocess.Popen:
    """Start ``companion`` with ``args`` (output discarded), SIGINT acting as Ctrl-C at a
    terminal even when this benchmark runs in the background (where it is ignored)."""
    return subprocess.Popen([sys.executable, "-m", "app.cli", *args], cwd=ROOT,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))


def started(out: Path, process: subprocess.Popen) -> float:
    """Wait until the run in ``out`` has written its configuration; the time then."""
    while not (out / "resolved_config.yaml").exists() and process.poll() is None:
        time.sleep(0.01)
    return time.monotonic()


def parses(row: list[str], width: int) -> bool:
    """Whether a CSV row has all ``width`` fields, each a number."""
    try:
        [float(v) for v in row]
    except ValueError:
        return False
    return len(row) == width


def read_log(path: Path) -> tuple[list[list[str]], int]:
    """A log's rows without the wall time (the last column), and how many rows do not
    parse."""
    with path.open(newline="") as fh:
        header, *rows = csv.reader(fh)
    return [r[:-1] for r in rows], sum(not parses(r, len(header)) for r in rows)


def duplicated(name: str, rows: list[list[str]]) -> int:
    """Rows of the log ``name`` whose key (episode; transitions and updates) came before."""
    keys = [tuple(r[:LOGS[name]]) for r in rows]
    return len(keys) - len(set(keys))


def check(out: Path, reference: dict[str, list[list[str]]]) -> dict:
    """What a resumed run left in ``out``."""
    result = {"bad_rows": 0, "duplicated_rows": 0, "equal_to_straight": True}
    for name in LOGS:
        rows, bad = read_log(out / name)
        result["bad_rows"] += bad
        result["duplicated_rows"] += duplicated(name, rows)
        result["equal_to_straight"] &= rows == reference[name]
    result["tmp_files"] = len(list(out.rglob(".*.tmp")))
    result["lock_left"] = (out / ".lock").exists()
    summary = out / "summary.json"
    result["finished"] = (summary.exists()
                          and json.loads(summary.read_text())["transitions"] >= TOTAL)
    return result


def trial(config: Path, out: Path, sig: signal.Signals, delay: float) -> dict:
    """Kill a training ``delay`` s into its span with ``sig``, resume it, check it."""
    shutil.rmtree(out, ignore_errors=True)
    args = ["train", "policy", "--out", str(out), "--no-progress"]
    first = companion(*args, "--config", str(config))
    t0 = started(out, first)
    while first.poll() is None and time.monotonic() - t0 < delay:
        time.sleep(0.005)
    if first.poll() is None:
        where = "after the training" if (out / "summary.json").exists() else "in the training"
        first.send_signal(sig)
    else:
        where = "after the process ended"
    code = first.wait()
    resumed = companion(*args, "--resume").wait()
    return {"exit": code, "where": where, "resume_exit": resumed}


def main() -> None:
    """Run the trials; print one JSON line per signal and the totals."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--n", type=int, default=20, help="kills of each kind (default 20)")
    parser.add_argument("--out", type=Path, default=Path("runs/bench-kill-training"))
    parser.add_argument("--seed", type=int, default=0, help="seed of the kill times")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    config = args.out / "tiny.yaml"
    config.write_text(CONFIG)
    straight = args.out / "straight"
    shutil.rmtree(straight, ignore_errors=True)
    process = companion("train", "policy", "--config", str(config), "--out", str(straight),
                        "--no-progress")
    t0 = started(straight, process)
    assert process.wait() == 0, "the uninterrupted run failed"
    span = time.monotonic() - t0
    reference = {name: read_log(straight / name)[0] for name in LOGS}
    print(json.dumps({"straight_run_span_s": round(span, 2),
                      "episodes": len(reference["train_log.csv"]),
                      "validations": len(reference["eval_log.csv"]),
                      "duplicated_rows": sum(duplicated(n, r) for n, r in reference.items())}),
          flush=True)
    rng = np.random.default_rng(args.seed)
    start = time.monotonic()
    for name, sig in KINDS.items():
        seen: dict = collections.defaultdict(int)
        for i in range(args.n):
            out = args.out / f"{name}-{i}"
            t = trial(config, out, sig, float(rng.uniform(0, span)))
            checked = check(out, reference)
            seen[f"{t['where']}: exit {t['exit']}"] += 1
            seen["resume exit 0"] += t["resume_exit"] == 0
            for key in ("bad_rows", "duplicated_rows", "tmp_files"):
                seen[key] += checked[key]
            for key in ("equal_to_straight", "finished", "lock_left"):
                seen[key] += checked[key]
        print(json.dumps({"signal": name, "kills": args.n, **seen}), flush=True)
    print(json.dumps({"wall_s": round(time.monotonic() - start)}))


if __name__ == "__main__":
    main()
