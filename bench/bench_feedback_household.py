"""The household "dislikes dancing" scenario with and without adaptation, side by side.

    python bench/bench_feedback_household.py [--seed 0] [--out runs/bench-feedback]

Runs worlds/dislikes_dancing.yaml (two simulated hours; Edith scolds the robot when she sees
it dance and praises a chat) twice as `companion run` processes at once: with
`--no-adaptation` (feedback heard and credited, the DQN alone chooses) and with
`--no-memory` (the robot adapts during the run, starting from nothing). For each it prints
the dances started after the third scolding of dancing, per hour, the chats per hour over
the same span, and RSR. A robot that stops dancing after the first scolding is never
scolded three times: its span then starts at its last scolding.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path

WORLD = Path(__file__).resolve().parents[1] / "worlds" / "dislikes_dancing.yaml"
ARMS = {"without adaptation": "--no-adaptation", "adapting": "--no-memory"}


def figures(folder: Path) -> dict[str, float]:
    """Dances and chats per hour after the third credited scolding of dancing (after the
    last one when there were fewer: a robot that stops after one is never scolded thrice),
    and RSR."""
    events = [json.loads(line) for line in (folder / "events.jsonl").open()]
    end = events[-1]["t"]
    scolded = [e["t"] for e in events if e["kind"] == "credited"
               and e["action"] == "sing_dance" and e["reward"] < 0]
    since = scolded[min(2, len(scolded) - 1)] if scolded else 0.0
    hours = max(end - since, 1e-9) / 3600

    def started(action: str) -> int:
        return sum(e["kind"] == "action" and e["action"] == action and e["t"] > since
                   for e in events)

    metrics = json.loads((folder / "metrics.json").read_text())
    return {"third_scolding_s": round(since, 1), "scoldings": len(scolded),
            "dances_per_hour": started("sing_dance") / hours,
            "chats_per_hour": started("chat") / hours, "rsr": metrics["rsr"],
            "choices_by_preference": metrics["choices_by_preference"]}


def main() -> None:
    """Run both arms and print the comparison."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--out", type=Path, default=Path("runs/bench-feedback"))
    args = parser.parse_args()
    procs = {arm: subprocess.Popen(
        [sys.executable, "-m", "app.cli", "run", str(WORLD), "--seed", str(args.seed),
         "--out", str(args.out / f"{flag[2:]}-seed{args.seed}"), "--overwrite", flag,
         "--no-progress"], stdout=subprocess.DEVNULL) for arm, flag in ARMS.items()}
    for arm, proc in procs.items():
        if proc.wait() != 0:
            sys.exit(f"{arm}: companion run exited {proc.returncode}")
    rows = {arm: figures(args.out / f"{flag[2:]}-seed{args.seed}") for arm, flag in ARMS.items()}
    print(f"seed {args.seed}: | arm | scoldings | span from s | dances / h after | chats / h after "
          "| RSR % | choices by preference |")
    for arm, r in rows.items():
        print(f"| {arm} | {r['scoldings']} | {r['third_scolding_s']:.0f} "
              f"| {r['dances_per_hour']:.2f} "
              f"| {r['chats_per_hour']:.2f} | {100 * r['rsr']:.2f} "
              f"| {r['choices_by_preference']} |")
    base, adapt = rows["without adaptation"], rows["adapting"]
    if base["dances_per_hour"]:
        print(f"dances after the third scolding: "
              f"{1 - adapt['dances_per_hour'] / base['dances_per_hour']:+.0%} drop")


if __name__ == "__main__":
    main()
