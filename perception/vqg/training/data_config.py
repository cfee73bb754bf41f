"""The schema of the VQG data set's config (config/vqg_data.yaml, docs/vqg_data.md):
what the scenes hold, how visible a thing must be to count, and how many questions a frame gets."""

from __future__ import annotations

from pathlib import Path

from pydantic import Field, NonNegativeInt, PositiveInt, field_validator

from core.config_files import StrictModel, load_model
from core.paths import REPO_ROOT

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


class HouseholdConfig(StrictModel):
    """Frames of the shipped worlds taken by the robot's own head camera: the scenario runs
    on (people walk, sit, enter) and the robot is put down at random free places, now and
    then framing a person close up the way it does when it talks to them."""

    worlds: tuple[Path, ...] = Field(min_length=1)   # scenario files (relative: repository)
    splits: dict[str, NonNegativeInt]
    frames_per_run: PositiveInt       # frames from one run of a world before the next run
    frames_per_moment: PositiveInt    # robot poses rendered at one moment of the scenario
    advance_s: Span                   # scenario seconds between two moments
    person_share: float = Field(ge=0.0, le=1.0)
    person_distance: Span             # m from a framed person
    person_angle_deg: float = Field(gt=0.0, le=180.0)   # off the way they look, at most
    head_pitch: Span                  # rad (positive looks down), room frames
    face_pitch_jitter: float = Field(ge=0.0)            # rad around looking at the face
    head_yaw: Span                    # rad
    aim_jitter_deg: float = Field(ge=0.0)               # base heading off the person
    clearance_m: float = Field(gt=0.0)                  # robot centre to any footprint
    attempts: PositiveInt             # tries to find a free pose before giving up on one

    @field_validator("splits")
    @classmethod
    def _known_splits(cls, v: dict[str, int]) -> dict[str, int]:
        unknown = sorted(set(v) - set(SPLITS))
        if unknown:
            raise ValueError(f"unknown splits {unknown}; known: {list(SPLITS)}")
        return v

    def world_paths(self) -> list[Path]:
        """The scenario files, relative ones taken from the repository root."""
        return [w if w.is_absolute() else REPO_ROOT / w for w in self.worlds]


class VqgDataConfig(StrictModel):
    """Schema of ``config/vqg_data.yaml``."""

    splits: dict[str, NonNegativeInt]
    seed: NonNegativeInt
    examples: NonNegativeInt
    scene: SceneConfig
    visibility: VisibilityConfig
    questions: QuestionConfig
    household: HouseholdConfig


def load_vqg_data_config(path: str | Path | None = None) -> VqgDataConfig:
    """The packaged vqg_data.yaml, with the user file at ``path`` merged over it."""
    return load_model(VqgDataConfig, "vqg_data.yaml", path)
