"""Schema of ``config/detector.yaml`` (the detector's data recipe)."""

from __future__ import annotations

from pathlib import Path
from typing import Any, Self

from pydantic import Field, NonNegativeFloat, NonNegativeInt, PositiveInt, model_validator

from core.config_files import StrictModel, load_model
from core.paths import MODELS_DIR


class SplitsConfig(StrictModel):
    """Frames per split."""

    train: NonNegativeInt
    val: NonNegativeInt
    test: NonNegativeInt


class ImageConfig(StrictModel):
    """Rendered image size (pixels)."""

    width: PositiveInt
    height: PositiveInt


class DataConfig(StrictModel):
    """How ``companion data detector`` renders its frames and which boxes it keeps."""

    splits: SplitsConfig
    seed: NonNegativeInt
    image: ImageConfig
    distance: tuple[float, float]
    people_per_frame: tuple[NonNegativeInt, NonNegativeInt]
    empty_fraction: float = Field(ge=0.0, le=1.0)
    furniture_per_frame: tuple[NonNegativeInt, NonNegativeInt]
    edge_margin_deg: float = Field(ge=0.0, le=45.0)
    head_pitch: tuple[float, float]
    view_weights: tuple[NonNegativeFloat, NonNegativeFloat, NonNegativeFloat]
    examples: NonNegativeInt
    min_box_px: PositiveInt
    min_width_px: PositiveInt
    min_face_px: PositiveInt
    min_visible_fraction: float = Field(ge=0.0, le=1.0)
    face_max_angle_deg: float = Field(gt=0.0, le=180.0)

    @model_validator(mode="after")
    def _ranges(self) -> Self:
        for name in ("distance", "people_per_frame", "furniture_per_frame", "head_pitch"):
            lo, hi = getattr(self, name)
            if lo > hi:
                raise ValueError(f"{name}: lower bound {lo} exceeds upper bound {hi}")
        if sum(self.view_weights) <= 0:
            raise ValueError("view_weights: at least one weight must be positive")
        if self.distance[0] <= 0:
            raise ValueError("distance: must be positive")
        return self


class TrainConfig(StrictModel):
    """The ultralytics training run of ``companion train detector``."""

    model: str = Field(min_length=1)
    init_weights: Path | None = None
    threads: NonNegativeInt = 0
    imgsz: PositiveInt
    epochs: PositiveInt
    batch: PositiveInt
    workers: NonNegativeInt
    seed: NonNegativeInt
    optimizer: str
    lr0: float = Field(gt=0)
    cos_lr: bool
    close_mosaic: NonNegativeInt
    patience: PositiveInt
    extra: dict[str, Any]

    def ultralytics_args(self) -> dict[str, Any]:
        """Keyword arguments for ``YOLO.train`` (everything but the model yaml)."""
        args = self.model_dump(exclude={"model", "extra", "init_weights", "threads"})
        return {**args, **self.extra}


class DetectConfig(StrictModel):
    """How the detector runs on camera frames."""

    weights: Path | None = None
    imgsz: PositiveInt
    conf: float = Field(gt=0.0, lt=1.0)
    iou: float = Field(gt=0.0, lt=1.0)
    threads: int = Field(default=0, ge=0, le=256)


class DetectorConfig(StrictModel):
    """Schema of ``config/detector.yaml``."""

    data: DataConfig
    train: TrainConfig
    detect: DetectConfig


def load_detector_config(path: str | Path | None = None) -> DetectorConfig:
    """The packaged detector.yaml, with the user file at ``path`` merged over it."""
    return load_model(DetectorConfig, "detector.yaml", path)


DEFAULT_DETECTOR = MODELS_DIR / "detector.onnx"  # the robot's runtime file, exported from:
DEFAULT_TRAINED = MODELS_DIR / "detector.pt"     # the trained ultralytics weights
