"""Schema of ``config/mood_style.yaml``: the gate that decides whether the robot says
the style-transfer model's reply or the unstyled one with a mood opening, and the training
settings of the bigram language model the gate scores fluency with."""

from __future__ import annotations

from pathlib import Path

from pydantic import Field, field_validator

from core.config_files import StrictModel, load_model
from core.paths import REPO_ROOT


class GateConfig(StrictModel):
    """When a styled reply is said instead of the unstyled one."""

    min_content_kept: float = Field(ge=0, le=1)
    max_perplexity_ratio: float = Field(gt=0)
    keep_questions: bool
    min_new_bigram_count: int = Field(ge=0)


class MoodPhrases(StrictModel):
    """Phrases of each mood that the fallback says with the unstyled reply."""

    positive: list[str] = Field(min_length=1)
    negative: list[str] = Field(min_length=1)

    @field_validator("positive", "negative")
    @classmethod
    def _not_blank(cls, value: list[str]) -> list[str]:
        if any(not v.strip() for v in value):
            raise ValueError("a mood phrase must have words")
        return [v.strip() for v in value]


class FallbackConfig(StrictModel):
    """When the fallback says the unstyled reply as it is (``kept``) rather than after a
    mood phrase that would contradict it."""

    questions: bool   # whether a question gets a mood phrase
    contrary: MoodPhrases   # per mood: words of a reply that a phrase of the mood contradicts


class BigramConfig(StrictModel):
    """``companion train mood-lm``: the data and counts of the bigram model."""

    min_count: int = Field(ge=1)
    discount: float = Field(gt=0, lt=1)
    keep_min: int = Field(ge=1)
    conversation_repeat: int = Field(ge=1)


class MoodStyleConfig(StrictModel):
    """Everything the mood styling needs at run time, and its language model's training."""

    model_dir: Path
    gate: GateConfig
    openings: MoodPhrases
    closings: MoodPhrases
    fallback: FallbackConfig
    bigram: BigramConfig

    def resolved_model_dir(self) -> Path:
        """The model folder; a relative path is taken from the repository root."""
        return self.model_dir if self.model_dir.is_absolute() else REPO_ROOT / self.model_dir


def load_mood_config(path: str | Path | None = None) -> MoodStyleConfig:
    """Load ``config/mood_style.yaml``, overridden by the YAML file at ``path``."""
    return load_model(MoodStyleConfig, "mood_style.yaml", path)


BIGRAM_FILE = "bigram.npz"
