"""The robot's fast path for the YOLO detector: an ONNX export run by onnxruntime.

ultralytics' ``predict`` spends about as long on its per-call bookkeeping as the network
takes on a 320x240 frame, so the robot runs the exported graph itself: letterbox the frame
to the graph's fixed input, run it, keep each anchor's best class above ``conf`` and merge
boxes per class with OpenCV's NMS, as ultralytics does for ``predict``. The export comes
from :func:`perception.detector.training.train.export_onnx`; ultralytics writes the class names and
input size into the file's metadata.
"""

from __future__ import annotations

import ast
from pathlib import Path

import cv2
import numpy as np
import onnxruntime as ort

PAD_VALUE = 114  # ultralytics' letterbox grey


class OnnxYolo:
    """An ultralytics ONNX export (boxes ``cx, cy, w, h`` then one score per class)."""

    def __init__(self, path: Path, threads: int = 0) -> None:
        """Open ``path`` to run on ``threads`` CPU threads (0: onnxruntime's default, every
        core); raises whatever onnxruntime raises for an unreadable file."""
        options = ort.SessionOptions()
        options.intra_op_num_threads = threads
        options.inter_op_num_threads = 1
        # Idle worker threads sleep instead of spinning for the next frame: a spinning
        # thread would hold a core the camera's renderer or another run needs (1 ms slower
        # a frame; docs/speed.md).
        options.add_session_config_entry("session.intra_op.allow_spinning", "0")
        self.session = ort.InferenceSession(str(path), options,
                                            providers=["CPUExecutionProvider"])
        meta = self.session.get_modelmeta().custom_metadata_map
        self.names: dict[int, str] = ast.literal_eval(meta["names"])
        self.shape: tuple[int, int] = tuple(ast.literal_eval(meta["imgsz"]))  # (h, w)
        self.input = self.session.get_inputs()[0].name

    @property
    def imgsz(self) -> int:
        """The longer side of the graph's fixed input."""
        return max(self.shape)

    def _letterbox(self, frame: np.ndarray) -> tuple[np.ndarray, float, tuple[float, float]]:
        """``frame`` scaled to fit the input and padded around its centre; the scale and the
        (x, y) padding."""
        h, w = frame.shape[:2]
        th, tw = self.shape
        scale = min(th / h, tw / w)
        nw, nh = round(w * scale), round(h * scale)
        img = frame if (nw, nh) == (w, h) else cv2.resize(frame, (nw, nh),
                                                         interpolation=cv2.INTER_LINEAR)
        px, py = (tw - nw) / 2, (th - nh) / 2
        top, left = round(py - 0.1), round(px - 0.1)
        img = cv2.copyMakeBorder(img, top, th - nh - top, left, tw - nw - left,
                                 cv2.BORDER_CONSTANT, value=(PAD_VALUE,) * 3)
        return img, scale, (left, top)

    def predict(self, frame: np.ndarray, conf: float,
                iou: float) -> list[tuple[int, float, tuple[float, float, float, float]]]:
        """(class index, confidence, pixel ``x0, y0, x1, y1``) of the boxes kept in ``frame``
        (RGB uint8)."""
        img, scale, (left, top) = self._letterbox(frame)
        x = np.ascontiguousarray(img.transpose(2, 0, 1)[None], dtype=np.float32) / 255.0
        out = self.session.run(None, {self.input: x})[0][0].T  # (anchors, 4 + classes)
        scores = out[:, 4:]
        cls = scores.argmax(1)
        best = scores[np.arange(len(cls)), cls]
        keep = best > conf
        boxes, best, cls = out[keep, :4], best[keep], cls[keep]
        corners = np.column_stack([boxes[:, 0] - boxes[:, 2] / 2, boxes[:, 1] - boxes[:, 3] / 2,
                                   boxes[:, 2], boxes[:, 3]])
        idx = cv2.dnn.NMSBoxesBatched(corners.tolist(), best.tolist(), cls.tolist(), conf, iou)
        h, w = frame.shape[:2]
        found = []
        for i in np.asarray(idx, dtype=int).reshape(-1):
            x0, y0, bw, bh = corners[i]
            x0, x1 = np.clip([(x0 - left) / scale, (x0 + bw - left) / scale], 0, w)
            y0, y1 = np.clip([(y0 - top) / scale, (y0 + bh - top) / scale], 0, h)
            found.append((int(cls[i]), float(best[i]), (float(x0), float(y0), float(x1),
                                                         float(y1))))
        return found
