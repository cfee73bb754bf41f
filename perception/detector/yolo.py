"""The detector interface the skills use, and its ultralytics YOLO implementation.

``Detector.detect(frame)`` takes an RGB camera frame (H, W, 3, uint8) and returns
:class:`Detection` boxes in pixels. The find-people skill only sees this interface, so a
robot with a real camera can plug in its own YOLO weights (``detect.weights`` in
``config/detector.yaml``) or another detector entirely.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Protocol

import numpy as np

from core.errors import UserError
from perception.detector.config import DEFAULT_DETECTOR, DetectConfig, load_detector_config
from perception.detector.onnx_runtime import OnnxYolo
from perception.detector.ultralytics_offline import ultralytics_module


class DetectorFileError(UserError):
    """The detector's weights file is missing or unreadable."""


@dataclass(frozen=True)
class Detection:
    """One box: class name, confidence and pixel corners ``(x0, y0, x1, y1)``."""

    cls: str
    conf: float
    box: tuple[float, float, float, float]

    @property
    def centre(self) -> tuple[float, float]:
        """Box centre in pixels."""
        return (self.box[0] + self.box[2]) / 2, (self.box[1] + self.box[3]) / 2

    @property
    def height(self) -> float:
        """Box height in pixels."""
        return self.box[3] - self.box[1]

    @property
    def width(self) -> float:
        """Box width in pixels."""
        return self.box[2] - self.box[0]


class Detector(Protocol):
    """Anything that finds people and faces in an RGB frame."""

    def detect(self, frame: np.ndarray) -> list[Detection]:
        """Boxes found in ``frame`` (H, W, 3 uint8 RGB), most confident first."""
        ...


class UltralyticsYolo:
    """ultralytics weights behind the same ``names`` / ``imgsz`` / ``predict`` as
    :class:`~perception.detector.onnx_runtime.OnnxYolo`."""

    def __init__(self, path: Path, imgsz: int) -> None:
        """Open ``path``; raises whatever ultralytics raises for an unreadable file."""
        self.yolo = ultralytics_module().YOLO(str(path), task="detect")
        self.names: dict[int, str] = dict(self.yolo.names)
        self.imgsz = imgsz

    def predict(self, frame: np.ndarray, conf: float,
                iou: float) -> list[tuple[int, float, tuple[float, float, float, float]]]:
        """(class index, confidence, pixel ``x0, y0, x1, y1``) of the boxes kept in ``frame``
        (RGB uint8)."""
        bgr = np.ascontiguousarray(frame[..., ::-1])  # ultralytics reads arrays as BGR
        boxes = self.yolo.predict(bgr, imgsz=self.imgsz, conf=conf, iou=iou, device="cpu",
                                  verbose=False)[0].boxes
        return list(zip(boxes.cls.tolist(), boxes.conf.tolist(), boxes.xyxy.tolist(),
                        strict=True))


class YoloDetector:
    """A YOLO model run on the CPU at the camera's resolution: an ONNX export
    (``.onnx``, run by onnxruntime, the fast path) or any ultralytics weights file."""

    def __init__(self, weights: str | Path | None = None, imgsz: int | None = None,
                 conf: float | None = None, iou: float | None = None,
                 threads: int | None = None) -> None:
        """``weights`` None: the shipped detector; other arguments left at None take the
        value of ``detect:`` in ``config/detector.yaml`` (an ONNX export's input size
        is fixed in the file)."""
        path = Path(weights) if weights is not None else DEFAULT_DETECTOR
        if not path.is_file():
            raise DetectorFileError(f"{path}: detector weights not found (train them with "
                                    "`companion train detector`)")
        defaults = load_detector_config().detect
        try:
            self.model: OnnxYolo | UltralyticsYolo = (
                OnnxYolo(path, defaults.threads if threads is None else threads)
                if path.suffix == ".onnx"
                else UltralyticsYolo(path, defaults.imgsz if imgsz is None else imgsz))
        except Exception as exc:
            raise DetectorFileError(f"{path}: not a readable YOLO weights file ({exc})") from None
        self.path = path
        self.names = self.model.names
        self.imgsz = self.model.imgsz
        self.conf = defaults.conf if conf is None else conf
        self.iou = defaults.iou if iou is None else iou

    @classmethod
    def from_config(cls, cfg: DetectConfig | None = None) -> YoloDetector:
        """The detector described by ``detect:`` of the detector config (defaults if None)."""
        cfg = cfg or load_detector_config().detect
        return cls(cfg.weights, cfg.imgsz, cfg.conf, cfg.iou, cfg.threads)

    def detect(self, frame: np.ndarray) -> list[Detection]:
        """Boxes in ``frame`` (RGB uint8), most confident first."""
        if frame.ndim != 3 or frame.shape[2] != 3 or frame.dtype != np.uint8:
            raise ValueError(f"expected an (H, W, 3) uint8 RGB frame, got {frame.shape} "
                             f"{frame.dtype}")
        found = self.model.predict(frame, self.conf, self.iou)
        out = [Detection(self.names[int(c)], float(s), tuple(float(v) for v in xyxy))
               for c, s, xyxy in found]
        return sorted(out, key=lambda d: -d.conf)
