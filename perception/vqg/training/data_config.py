"""The schema of the VQG data set's config (app/defaults/vqg_data.yaml, docs/vqg_data.md):
what the scenes hold, how visible a thing must be to count, and how many questions a frame gets."""

from __future__ import annotations

from pathlib import Path

from pydantic import Field, NonNegativeInt, PositiveInt

from app.core.config_files import StrictModel, load_model

Span = tuple[float, float]
Count = tuple[NonNegativeInt, NonNegativeInt]
SPLITS = ("train", "val", "test")


class SceneConfig(StrictModel):
    """What one scene holds and how it is lit (ranges are inclusive ``[lo, hi]``)."""

    width: PositiveInt
    height: PositiveInt
    people: Count
    extra_furniture: Count
    surface_objects: Count
    floor_objects: Count
    balloons: Count
    candles: Count
    lit_fraction: float = Field(ge=0.0, le=1.0)
    person_height: Span
    size_jitter: float = Field(ge=0.0, lt=0.5)
    table_distance: Span
    head_pitch: Span
    depth: Span
    half_width: Span
    ambient: Span
    diffuse: Span
    specular: Span
    shadow_fraction: float = Field(ge=0.0, le=1.0)


class MinPixels(StrictModel):
    """Fewest visible mask pixels for a node to stay in the graph, per category."""

    object: PositiveInt
    candle: PositiveInt
    furniture: PositiveInt
    person: PositiveInt


class VisibilityConfig(StrictModel):
    """The visibility rule and the ``near`` relation."""

    min_pixels: MinPixels
    near_m: float = Field(gt=0.0)


class QuestionConfig(StrictModel):
    """How many questions each image gets."""

    max_frames: PositiveInt
    paraphrases: PositiveInt
    max_questions: PositiveInt
    fixed_wording: bool


class VqgDataConfig(StrictModel):
    """Schema of ``app/defaults/vqg_data.yaml``."""

    splits: dict[str, NonNegativeInt]
    seed: NonNegativeInt
    examples: NonNegativeInt
    scene: SceneConfig
    visibility: VisibilityConfig
    questions: QuestionConfig


def load_vqg_data_config(path: str | Path | None = None) -> VqgDataConfig:
    """The packaged vqg_data.yaml, with the user file at ``path`` merged over it."""
    return load_model(VqgDataConfig, "vqg_data.yaml", path)
