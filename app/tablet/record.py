"""What a run keeps for ``companion view``: beside its events and timeline, every
``replay.frame_period_s`` simulated seconds, the head camera with the detector's boxes as a
small JPEG in ``view/`` and the behaviour tree with each node's status as one line of
``view/trees.jsonl`` (at most ``replay.max_frames`` of each, so a soak's folder stays
bounded)."""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

import py_trees

from app.tablet.config import TabletConfig, load_tablet_config
from app.tablet.live import frame_jpeg
from core.checkpoint import atomic_write_bytes

VIEW_DIR = "view"
TREES = "trees.jsonl"


def frame_name(t: float) -> str:
    """The file name of the view frame taken at simulated time ``t``."""
    return f"frame-t{t:09.1f}.jpg"


def frame_time(name: str) -> float | None:
    """The simulated time in a view frame's file name (None for any other name)."""
    stem = name.removeprefix("frame-t").removesuffix(".jpg")
    if not name.startswith("frame-t") or not name.endswith(".jpg"):
        return None
    try:
        return float(stem)
    except ValueError:
        return None


class ViewFrames:
    """A post-tick handler of a run's tree that keeps the camera for the replay."""

    def __init__(self, out: Path, clock: Any, config: TabletConfig | None = None) -> None:
        self.config = config or load_tablet_config()
        self.folder = out / VIEW_DIR
        self.clock = clock
        self.left = self.config.replay.max_frames
        self._next = 0.0

    def __call__(self, tree: Any = None) -> None:
        """Save the latest camera frame (and the tree's statuses) once per period."""
        t = self.clock()
        if t < self._next or self.left <= 0:
            return
        store = py_trees.blackboard.Blackboard.storage
        frame = store.get("/frame")
        if frame is None:
            return
        self._next = t + self.config.replay.frame_period_s
        jpg = frame_jpeg(frame, store.get("/detections") or [], self.config.live)
        if jpg is None:
            return
        self.folder.mkdir(parents=True, exist_ok=True)
        atomic_write_bytes(self.folder / frame_name(t), jpg)
        self.left -= 1
        if tree is not None:
            line = json.dumps({"t": round(t, 2), "tree": py_trees.display.unicode_tree(
                tree.root, show_status=True)}, ensure_ascii=False) + "\n"
            _append_whole(self.folder / TREES, line.encode())


def _append_whole(path: Path, data: bytes) -> None:
    """Append ``data`` in one ``write`` call, so a killed run leaves no half line; a line
    the file system took only in part (a full disk) is cut off again before the error goes
    up."""
    fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_APPEND, 0o644)
    size = os.fstat(fd).st_size
    left = memoryview(data)
    try:
        while left:   # the rest of a short write: the file system's own error, if any
            left = left[os.write(fd, left):]
    except OSError:
        os.ftruncate(fd, size)
        raise
    finally:
        os.close(fd)
