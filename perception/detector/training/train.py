"""Training and evaluation of the person-and-face YOLO detector (``companion train|eval
detector``). The data set comes from ``companion data detector`` (docs/detector.md)."""

from __future__ import annotations

import json
import shutil
import statistics
import tempfile
import time
from pathlib import Path
from typing import Any

import cv2

from core.checkpoint import atomic_copy
from core.errors import UserError
from perception.detector.config import TrainConfig, load_detector_config
from perception.detector.ultralytics_offline import ultralytics_module
from perception.detector.yolo import DetectorFileError, YoloDetector


def _data_yaml(data: Path) -> Path:
    path = data / "data.yaml" if data.is_dir() else data
    if not path.is_file():
        raise UserError(f"{path}: no data set here (render one with `companion data detector "
                        f"--out {data}`)")
    return path


def train_detector(cfg: TrainConfig, data: Path, out: Path, resume: bool = False,
                   export: Path | None = None) -> Path:
    """Train YOLO from ``cfg.model`` on ``data``, from random weights or, with
    ``cfg.init_weights``, from an earlier detector of ours, on ``cfg.threads`` CPU threads
    (0: all). ultralytics writes its run into ``out`` (``weights/last.pt`` every epoch,
    ``results.csv``). ``resume`` continues ``out/weights/last.pt``. The best weights are
    copied to ``export`` when given (written to a temporary name first, then renamed).
    Returns the best weights' path."""
    ultralytics = ultralytics_module(verbose=True)
    if cfg.threads:
        ultralytics.utils.torch_utils.NUM_THREADS = cfg.threads
    yolo = ultralytics.YOLO
    out = out.resolve()
    last = out / "weights" / "last.pt"
    if resume:
        if not last.is_file():
            raise UserError(f"{last}: nothing to resume")
        model = yolo(str(last))
        model.train(resume=True)
    else:
        if last.exists():
            raise UserError(f"{out} already holds a training run; pass --resume to continue it "
                            "or choose another --out")
        init = cfg.init_weights
        if init is not None and not init.is_file():
            raise UserError(f"{init}: train.init_weights not found")
        model = yolo(cfg.model, task="detect")
        model.train(data=str(_data_yaml(data).resolve()), project=str(out.parent),
                    name=out.name, exist_ok=True, device="cpu", amp=False,
                    pretrained=str(init.resolve()) if init is not None else False,
                    plots=False, val=True, **cfg.ultralytics_args())
    best = out / "weights" / "best.pt"
    if export is not None:
        atomic_copy(best, export)
        export_onnx(best, export.with_suffix(".onnx"), cfg.imgsz)
    return best


def onnx_input_shape(imgsz: int, width: int, height: int) -> tuple[int, int]:
    """(h, w) of the graph input for a ``width`` x ``height`` camera whose longer side is
    scaled to ``imgsz``: each side rounded up to YOLO's stride of 32."""
    scale = imgsz / max(width, height)
    return tuple(-(-round(side * scale) // 32) * 32 for side in (height, width))


def export_onnx(weights: Path, dst: Path, imgsz: int) -> Path:
    """Export ultralytics ``weights`` to an ONNX graph at ``dst`` (written whole or not at
    all) with the fixed input the head camera's frames letterbox to; see
    :mod:`perception.detector.onnx_runtime`."""
    if weights.suffix != ".pt":
        raise DetectorFileError(f"{weights}: expected ultralytics .pt weights to export")
    image = load_detector_config().data.image
    shape = onnx_input_shape(imgsz, image.width, image.height)
    YoloDetector(weights)  # names a missing or unreadable file
    with tempfile.TemporaryDirectory() as scratch:  # ultralytics writes beside the weights
        src = Path(scratch) / weights.name
        shutil.copyfile(weights, src)
        onnx = ultralytics_module().YOLO(str(src), task="detect").export(
            format="onnx", imgsz=shape, simplify=True, dynamic=False, device="cpu")
        atomic_copy(Path(onnx), dst)
    return dst


def _image(path: Path) -> Any:
    """The BGR image at ``path``; an unreadable one is named."""
    image = cv2.imread(str(path))
    if image is None:
        raise UserError(f"{path}: not a readable image; render the data set again with "
                        "`companion data detector`")
    return image


def latency_ms(detector: YoloDetector, frames: list[Path], repeats: int = 100) -> float:
    """Median wall time (ms) of one ``detect`` call over ``repeats`` calls on these frames
    (after two warm-up calls)."""
    images = [cv2.cvtColor(_image(f), cv2.COLOR_BGR2RGB) for f in frames]
    for img in images[:2]:
        detector.detect(img)
    times = []
    for i in range(repeats):
        t0 = time.perf_counter()
        detector.detect(images[i % len(images)])
        times.append((time.perf_counter() - t0) * 1000.0)
    return statistics.median(times)


def evaluate_detector(weights: Path | None, data: Path, split: str = "test",
                      imgsz: int | None = None, iou: float | None = None) -> dict[str, Any]:
    """mAP figures on ``split`` of the data set and the median CPU latency per frame. Boxes
    are merged with the NMS overlap ``iou`` (default: the robot's ``detect.iou``); every
    confidence counts (ultralytics' 0.001), as mAP needs the whole precision-recall curve."""
    data_yaml = _data_yaml(data)
    detector = YoloDetector(weights, imgsz=imgsz, iou=iou)
    with tempfile.TemporaryDirectory() as scratch:  # ultralytics writes a val folder
        val = ultralytics_module().YOLO(str(detector.path), task="detect").val
        metrics = val(data=str(data_yaml.resolve()), split=split, imgsz=detector.imgsz,
                      iou=detector.iou, batch=16, device="cpu", plots=False, verbose=False,
                      workers=0, project=scratch)
    box = metrics.box
    ap50 = dict(zip(box.ap_class_index.tolist(), box.ap50.tolist(), strict=True))
    ap = dict(zip(box.ap_class_index.tolist(), box.ap.tolist(), strict=True))
    index = {name: i for i, name in detector.names.items()}
    root = data_yaml.parent
    frames = sorted((root / "images" / split).glob("*.png"))[:20]
    return {
        "weights": str(detector.path),
        "split": split,
        "person_map50": ap50.get(index["person"], 0.0),
        "person_map50_95": ap.get(index["person"], 0.0),
        "face_map50": ap50.get(index["face"], 0.0),
        "face_map50_95": ap.get(index["face"], 0.0),
        "latency_ms_median": latency_ms(detector, frames),
        "imgsz": detector.imgsz,
        "nms_iou": detector.iou,
    }


def write_json(obj: dict[str, Any], path: Path) -> None:
    """Write ``obj`` as indented JSON."""
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(obj, indent=2) + "\n")
