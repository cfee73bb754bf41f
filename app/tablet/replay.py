"""``companion view RUN_DIR``: the live view over a finished run, at any time a slider picks.

The run folder already holds what the view needs: ``timeline.csv`` (drives, motivations,
mood and action at each homeostasis step), ``events.jsonl`` (why each action started,
pre-emptions, credited feedback, what was heard and said), ``view/`` (the head camera and
the tree with each node's status every few seconds, :mod:`app.tablet.record`) and
``scenario.yaml`` (the personality, for the desired ranges). A folder without
``view/trees.jsonl`` shows the tree as the run left it (``tree.txt``).
"""

from __future__ import annotations

import bisect
import csv
import io
import json
from pathlib import Path
from typing import Any

from app.tablet.cards import FileRegistry
from app.tablet.config import TabletConfig
from app.tablet.live import SnapshotSlot, ranges
from app.tablet.record import TREES, VIEW_DIR, frame_time
from app.tablet.replies import ReplyLog
from core.config_files import read_yaml
from core.errors import UserError
from core.files import DATA_LIMIT, read_text
from mind.homeostasis import Homeostasis
from mind.personality import DRIVES, MOTIVATIONS, load_personality

WHY_KINDS = ("action", "preempted", "credited")


class ReplayView:
    """A finished run's snapshots by time (the backend of ``companion view``)."""

    kind = "replay"

    def __init__(self, run_dir: Path, config: TabletConfig) -> None:
        self.config, self.run_dir = config, run_dir
        for name in ("timeline.csv", "events.jsonl"):
            if not (run_dir / name).is_file():
                raise UserError(f"{run_dir}: not a run folder (no {name})")
        self.replies = ReplyLog(limit=1)      # a replay is not spoken to
        self.slot = SnapshotSlot()
        self.files = FileRegistry(run_dir, limit=config.replay.max_frames + 10)
        self.rows = list(csv.DictReader(io.StringIO(read_text(run_dir / "timeline.csv",
                                                              DATA_LIMIT))))
        if not self.rows:
            raise UserError(f"{run_dir}/timeline.csv: no rows (the run ended at once)")
        self.times = [float(r["t"]) for r in self.rows]
        self.events = [json.loads(line) for line in
                       read_text(run_dir / "events.jsonl", DATA_LIMIT).splitlines() if line]
        self.event_times = [float(e["t"]) for e in self.events]
        scenario = (read_yaml(run_dir / "scenario.yaml") if (run_dir / "scenario.yaml").is_file()
                    else {})
        self._ranges = ranges(Homeostasis(load_personality(scenario.get("personality"))))
        tree = run_dir / "tree.txt"
        self._tree = read_text(tree).split("\n\nLast tick:\n")[-1] if tree.is_file() else ""
        trees = run_dir / VIEW_DIR / TREES
        self.trees = [json.loads(line) for line in read_text(trees, DATA_LIMIT).splitlines()
                      if line] if trees.is_file() else []
        self.tree_times = [float(e["t"]) for e in self.trees]
        self.frames = self._frames()

    def _frames(self) -> list[tuple[float, str]]:
        folder = self.run_dir / VIEW_DIR
        found = []
        for path in sorted(folder.iterdir()) if folder.is_dir() else []:
            t = frame_time(path.name)
            file_id = self.files.add(path) if t is not None else None
            if file_id is not None:
                found.append((t, f"/api/file/{file_id}"))
        return sorted(found)

    def _tree_at(self, t: float) -> str:
        k = bisect.bisect_right(self.tree_times, t) - 1
        return self.trees[k]["tree"] if k >= 0 else self._tree

    def index(self) -> dict[str, Any]:
        """The slider's span: the run's duration, the timeline's step, the frames kept."""
        step = self.times[1] - self.times[0] if len(self.times) > 1 else 1.0
        return {"duration": self.times[-1], "step": round(step, 3), "frames": len(self.frames),
                "rows": len(self.rows)}

    def snapshot(self) -> tuple[int, bytes]:
        """Replays push nothing: the page asks :meth:`snapshot_at` instead."""
        return self.slot.get()

    def snapshot_at(self, t: float) -> dict[str, Any]:
        """The mind at simulated time ``t`` (the last timeline row and events up to it)."""
        row = self.rows[max(bisect.bisect_right(self.times, t) - 1, 0)]
        upto = self.events[:bisect.bisect_right(self.event_times, t)]
        latest = {}
        for e in reversed(upto):
            if e["kind"] in WHY_KINDS and e["kind"] not in latest:
                latest[e["kind"]] = e
            if len(latest) == len(WHY_KINDS):
                break
        said = [{"t": e["t"], "input": e.get("in_reply_to", ""), "text": e["text"],
                 "route": e.get("route", "")} for e in upto
                if e["kind"] == "say" and e.get("in_reply_to")]
        k = bisect.bisect_right([f[0] for f in self.frames], t) - 1
        action = latest.get("action", {})
        return {
            "t": float(row["t"]),
            "mood": {"value": float(row["mood"]), "positive": row["mood_positive"] == "1"},
            "drives": {d: float(row[d]) for d in DRIVES},
            "motivations": {m: float(row[f"m_{m}"]) for m in MOTIVATIONS},
            "ranges": self._ranges, "action": row["action"],
            "why": {"reason": action.get("reason"), "since": action.get("t"),
                    "preempted": latest.get("preempted"), "credited": latest.get("credited")},
            "tree": self._tree_at(t),
            "frame_src": self.frames[k][1] if k >= 0 else None,
            "frame_t": self.frames[k][0] if k >= 0 else None,
            "dialogue": said[-self.config.live.dialogue_lines:],
        }
