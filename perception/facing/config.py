"""Schema of ``config/facing.yaml``: the crops, the network, training and the bars."""

from __future__ import annotations

from pathlib import Path
from typing import Self

from pydantic import Field, NonNegativeInt, PositiveFloat, PositiveInt, model_validator

from core.config_files import StrictModel, load_model
from core.paths import MODELS_DIR
from perception.detector.config import SplitsConfig

DEFAULT_FACING_MODEL = MODELS_DIR / "facing.pt"


class CropConfig(StrictModel):
    """The network's input size (pixels)."""

    width: PositiveInt
    height: PositiveInt


class FacingDataConfig(StrictModel):
    """How ``companion data facing`` renders people and crops them."""

    splits: SplitsConfig
    seed: NonNegativeInt
    distance: tuple[PositiveFloat, PositiveFloat]
    people_per_frame: tuple[PositiveInt, PositiveInt]
    crop: CropConfig
    pad: float = Field(ge=0.0, le=0.5)
    min_box_px: PositiveInt
    min_visible_fraction: float = Field(ge=0.0, le=1.0)

    @model_validator(mode="after")
    def _ranges(self) -> Self:
        for name in ("distance", "people_per_frame"):
            lo, hi = getattr(self, name)
            if lo > hi:
                raise ValueError(f"{name}: lower bound {lo} exceeds upper bound {hi}")
        return self


class FacingModelConfig(StrictModel):
    """The CNN: channels per stage, angle bins, dropout."""

    channels: list[PositiveInt] = Field(min_length=1)
    bins: int = Field(ge=4, le=72)
    dropout: float = Field(ge=0.0, lt=1.0)


class FacingTrainConfig(StrictModel):
    """The training loop's hyper-parameters."""

    epochs: PositiveInt
    batch: PositiveInt
    lr: PositiveFloat
    weight_decay: float = Field(ge=0.0)
    label_smoothing: float = Field(ge=0.0, lt=1.0)
    flip: bool
    seed: NonNegativeInt
    threads: NonNegativeInt


class FacingEvalConfig(StrictModel):
    """The bars of ``companion eval facing``."""

    bars: dict[str, float]


class FacingConfig(StrictModel):
    """Schema of ``config/facing.yaml``."""

    data: FacingDataConfig
    model: FacingModelConfig
    train: FacingTrainConfig
    eval: FacingEvalConfig


def load_facing_config(path: str | Path | None = None) -> FacingConfig:
    """The packaged facing.yaml, with the user file at ``path`` merged over it."""
    return load_model(FacingConfig, "facing.yaml", path)
