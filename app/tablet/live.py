"""The live view of the robot's mind: snapshots of the blackboard, the tree and the camera,
built in the run loop at most ``snapshot_hz`` times per wall second and handed to the web
server as ready JSON bytes (:class:`SnapshotSlot`), so that any number of viewers costs the
run one snapshot."""

from __future__ import annotations

import base64
import json
import threading
import time
from typing import Any

import cv2
import numpy as np
import py_trees

from app.tablet.config import LiveConfig
from app.tablet.replies import ReplyLog
from mind.homeostasis import Homeostasis
from mind.personality import DRIVES, MOTIVATIONS

REASON_KINDS = ("action", "preempted", "credited")   # events that explain the current action
CARE_SHOWN = 5                                       # the latest care alerts on the page
BOX_COLOUR = (255, 200, 0)   # RGB


class SnapshotSlot:
    """The latest snapshot, numbered: written by one thread, read by the server's."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self.seq = 0
        self._data = b"{}"

    def put(self, snapshot: dict[str, Any]) -> None:
        """Make ``snapshot`` the latest (serialised once here)."""
        data = json.dumps(snapshot, separators=(",", ":"), default=_plain).encode()
        with self._lock:
            self.seq += 1
            self._data = data

    def get(self) -> tuple[int, bytes]:
        """``(seq, JSON bytes)`` of the latest snapshot."""
        with self._lock:
            return self.seq, self._data


def _plain(value: Any) -> Any:
    if isinstance(value, np.ndarray):
        return [round(float(v), 4) for v in value]
    if isinstance(value, np.generic):
        return value.item()
    return str(value)


def frame_jpeg(frame: np.ndarray, boxes: list[Any], cfg: LiveConfig) -> bytes | None:
    """``frame`` (RGB) with the detector's ``boxes`` drawn, scaled to the view's width, as
    JPEG bytes (None when it cannot be encoded)."""
    img = cv2.cvtColor(frame, cv2.COLOR_RGB2BGR)
    for d in boxes:
        x0, y0, x1, y1 = (int(v) for v in d.box)
        cv2.rectangle(img, (x0, y0), (x1, y1), BOX_COLOUR[::-1], 2)
        cv2.putText(img, f"{d.cls} {d.conf:.2f}", (x0 + 2, max(y0 - 4, 10)),
                    cv2.FONT_HERSHEY_SIMPLEX, 0.4, BOX_COLOUR[::-1], 1)
    h, w = img.shape[:2]
    if w > cfg.frame_width:
        img = cv2.resize(img, (cfg.frame_width, round(h * cfg.frame_width / w)),
                         interpolation=cv2.INTER_AREA)
    ok, jpg = cv2.imencode(".jpg", img, [cv2.IMWRITE_JPEG_QUALITY, cfg.jpeg_quality])
    return jpg.tobytes() if ok else None


def ranges(homeostasis: Homeostasis) -> dict[str, list[float]]:
    """Each motivation's desired range ``[low, high]``."""
    return {m: [float(lo), float(hi)] for m, lo, hi in
            zip(MOTIVATIONS, homeostasis.lower, homeostasis.upper, strict=True)}


class MindView:
    """Builds the live view's snapshots from a run's context and tree (in the run loop)."""

    def __init__(self, ctx: Any, root: py_trees.behaviour.Behaviour, replies: ReplyLog,
                 slot: SnapshotSlot, cfg: LiveConfig) -> None:
        self.ctx, self.root, self.replies, self.slot, self.cfg = ctx, root, replies, slot, cfg
        self._ranges = ranges(ctx.homeostasis)
        self._seen = 0                      # events already looked through
        self._latest: dict[str, dict[str, Any]] = {}
        self._care: list[dict[str, Any]] = []   # the latest care alerts
        self._frame_t = None
        self._frame: str | None = None
        self._next = 0.0                    # wall time of the next snapshot
        self.built = 0

    def __call__(self, tree: Any = None) -> None:
        """A post-tick handler: publish a snapshot when one is due by the wall clock."""
        now = time.perf_counter()
        if now >= self._next:
            self._next = now + 1.0 / self.cfg.snapshot_hz
            self.publish()

    def publish(self) -> None:
        """Build a snapshot now and put it in the slot."""
        self.slot.put(self.snapshot())
        self.built += 1

    def snapshot(self) -> dict[str, Any]:
        """The mind as it stands after the last tick."""
        store = py_trees.blackboard.Blackboard.storage
        events = self.ctx.events.events
        for e in events[self._seen:]:
            if e["kind"] in REASON_KINDS:
                self._latest[e["kind"]] = e
            elif e["kind"] == "care_alert":
                self._care = [*self._care, {k: e.get(k) for k in ("t", "person", "care", "text")}
                              ][-CARE_SHOWN:]
        self._seen = len(events)
        mood = store.get("/mood") or {}
        frame_t = store.get("/frame_t")
        if frame_t != self._frame_t and store.get("/frame") is not None:
            jpg = frame_jpeg(store["/frame"], store.get("/detections") or [], self.cfg)
            self._frame = base64.b64encode(jpg).decode() if jpg else None
            self._frame_t = frame_t
        heard = store.get("/heard") or []
        return {
            "wall": round(time.time(), 3),   # when it was built (the bench's delivery delay)
            "t": round(self.ctx.now, 2),
            "mood": {"value": round(float(mood.get("value", 0.0)), 4),
                     "positive": bool(mood.get("positive", True))},
            "drives": dict(zip(DRIVES, store.get("/drives"), strict=True)),
            "motivations": dict(zip(MOTIVATIONS, store.get("/motivations"), strict=True)),
            "ranges": self._ranges,
            "action": store.get("/action"),
            "why": self._why(),
            "answering": [h.text for h in heard],
            "tree": py_trees.display.unicode_tree(self.root, show_status=True),
            "frame": self._frame,
            "frame_t": frame_t if frame_t is not None and np.isfinite(frame_t) else None,
            "detections": [{"cls": d.cls, "conf": round(d.conf, 3)}
                           for d in store.get("/detections") or []],
            "dialogue": self.replies.last(self.cfg.dialogue_lines),
            "care_alerts": self._care,
        }

    def _why(self) -> dict[str, Any]:
        action = self._latest.get("action", {})
        return {"reason": action.get("reason"), "since": action.get("t"),
                "preempted": self._latest.get("preempted"),
                "credited": self._latest.get("credited")}
