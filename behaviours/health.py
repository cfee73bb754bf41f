"""The robot's own watch over its sensors and motors (docs/reliability.md).

:class:`SensorHealth` looks at what the sensors give, never at the simulator's fault flags:

- a camera frame that is black (mean brightness under ``BLACK_LEVEL``) or that repeats the
  previous frame's sequence number (a frozen driver) is not passed to the detector;
- a detector that raises or times out costs that frame only: the next frame retries;
- a joint whose measured angle stays more than ``JOINT_ERROR_RAD`` from its command for
  ``JOINT_ERROR_S`` has a failed motor.

Each problem is logged once as a ``fault`` event when it appears (with the recovery the
robot applies) and as ``recovered`` when it goes away.
"""

from __future__ import annotations

from typing import Any

import numpy as np

BLACK_LEVEL = 3.0       # mean 8-bit brightness below which a frame is black
JOINT_ERROR_RAD = 0.35  # tracking error of a failed joint
JOINT_ERROR_S = 1.0     # ... held this long
RECOVERY = {
    "camera_black": "skip the frame (no detections) until frames come back",
    "camera_frozen": "skip repeated frames (no detections) until new ones come",
    "detector_error": "skip the frame; the next frame retries the detector",
    "detector_timeout": "skip the frame; the next frame retries the detector",
    "joint_failure": "go on without the joint: a posture it can't reach times out and "
                     "the action fails (posture_timeout)",
}


class SensorHealth:
    """Tracks sensor and motor problems; ``emit`` logs events (``emit(kind, **fields)``)."""

    def __init__(self, emit: Any) -> None:
        self.emit = emit
        self._seq = -1
        self._active: dict[str, float] = {}      # problem -> since (s)
        self._joint_since: dict[str, float] = {}

    def _set(self, problem: str, on: bool, now: float, **details: Any) -> None:
        if on and problem not in self._active:
            self._active[problem] = now
            self.emit("fault", fault=problem, recovery=RECOVERY[problem], **details)
        elif not on and problem in self._active:
            self.emit("recovered", fault=problem, after_s=round(now - self._active.pop(problem), 2))

    def frame_usable(self, frame: np.ndarray, seq: int, now: float) -> bool:
        """Whether ``frame`` (with the camera's sequence number ``seq``) is worth detecting."""
        black = float(frame.mean()) < BLACK_LEVEL
        frozen = seq == self._seq
        self._seq = seq
        self._set("camera_black", black, now)
        self._set("camera_frozen", frozen and not black, now)
        return not (black or frozen)

    def detect(self, detector: Any, frame: np.ndarray, now: float) -> list:
        """``detector.detect(frame)``, or no detections when it fails (logged)."""
        try:
            detections = detector.detect(frame)
        except TimeoutError as exc:
            self._set("detector_timeout", True, now, error=str(exc)[:200])
            return []
        except Exception as exc:   # any detector failure costs this frame only
            self._set("detector_error", True, now, error=f"{type(exc).__name__}: {exc}"[:200])
            return []
        self._set("detector_timeout", False, now)
        self._set("detector_error", False, now)
        return detections

    def joints(self, errors: dict[str, float], now: float) -> None:
        """Check the joints' tracking errors (rad, by name)."""
        for name, error in errors.items():
            if error > JOINT_ERROR_RAD:
                since = self._joint_since.setdefault(name, now)
                if now - since >= JOINT_ERROR_S:
                    self._set("joint_failure", True, now, joint=name, error_rad=error)
            else:
                self._joint_since.pop(name, None)
        if not self._joint_since:
            self._set("joint_failure", False, now)
