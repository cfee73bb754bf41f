"""The personality: a validated YAML config holding every number of the homeostasis model."""

from __future__ import annotations

from pathlib import Path
from typing import Literal

from pydantic import Field, field_validator, model_validator

from core.config_files import StrictModel, load_model

DRIVES = ("energy", "safety_rest", "belonging", "esteem", "self_actualisation", "curiosity")
MOTIVATIONS = ("survival", "rest", "relationship", "achievement", "social_interaction", "asking")
ACTIONS = ("charge", "rest", "find_people", "sing_dance", "ask_question", "chat", "stand_by")
STIMULI = ("overheat", "human_present", "encouragement")
STAND_BY = ACTIONS.index("stand_by")

Drive = Literal[DRIVES]
Motivation = Literal[MOTIVATIONS]
Action = Literal[ACTIONS]
Stimulus = Literal[STIMULI]


class DriveGrowth(StrictModel):
    """How one drive grows each step (Table 4.1)."""

    growth: Literal["linear", "exponential"]
    rate: float | None = Field(default=None, ge=0)
    tau: float | None = Field(default=None, gt=0)
    grows_during_actions: bool

    @model_validator(mode="after")
    def _needs_parameter(self) -> DriveGrowth:
        if self.growth == "linear" and self.rate is None:
            raise ValueError("linear growth needs `rate`")
        if self.growth == "exponential" and self.tau is None:
            raise ValueError("exponential growth needs `tau`")
        return self


class ActionEffect(StrictModel):
    """The drive an action satisfies, by how much, and over how many steps (Table 4.2)."""

    drive: Drive | None
    decrease: float = Field(ge=0, le=1)
    duration: int = Field(ge=1)


class StimulusEffect(StrictModel):
    """One f_st entry of Table 4.3."""

    weight: float
    when: Literal["active", "inactive"]


class RewardWeights(StrictModel):
    """kappa, lambda and nu of eq. 3.7."""

    kappa: float = Field(gt=0)
    lambda_: float = Field(alias="lambda", lt=0)
    nu: int = Field(ge=0, le=len(MOTIVATIONS))


class MoodWeights(StrictModel):
    """Weights and threshold of eq. 3.6."""

    drive_weights: dict[Drive, float]
    encouragement_weight: float = Field(ge=0)
    emotion_weight: float = Field(ge=0)
    threshold: float

    @field_validator("drive_weights")
    @classmethod
    def _complete_and_normalised(cls, v: dict[str, float]) -> dict[str, float]:
        missing = [d for d in DRIVES if d not in v]
        if missing:
            raise ValueError(f"missing drives {missing}")
        if abs(sum(v.values()) - 1.0) > 1e-6:
            raise ValueError(f"weights must sum to 1, they sum to {sum(v.values()):.4f}")
        return v


class Personality(StrictModel):
    """Every parameter of the homeostasis model; see ``config/personality.yaml``."""

    drives: dict[Drive, DriveGrowth]
    actions: dict[Action, ActionEffect]
    stimulus_effects: dict[Motivation, dict[Stimulus, StimulusEffect]]
    desired_ranges: dict[Motivation, tuple[float, float]]
    reward: RewardWeights
    secure_threshold: float = Field(gt=0, le=1)
    mood: MoodWeights

    @field_validator("drives", "actions", "desired_ranges")
    @classmethod
    def _complete(cls, v: dict[str, object], info: object) -> dict[str, object]:
        names = {"drives": DRIVES, "actions": ACTIONS, "desired_ranges": MOTIVATIONS}
        missing = [n for n in names[info.field_name] if n not in v]  # type: ignore[attr-defined]
        if missing:
            raise ValueError(f"missing entries {missing}")
        return v

    @field_validator("desired_ranges")
    @classmethod
    def _ordered(cls, v: dict[str, tuple[float, float]]) -> dict[str, tuple[float, float]]:
        for name, (low, high) in v.items():
            if not 0.0 <= low < high:
                raise ValueError(f"{name}: need 0 <= lower < upper, got [{low}, {high}]")
        return v

    @model_validator(mode="after")
    def _stand_by_satisfies_nothing(self) -> Personality:
        if self.actions["stand_by"].drive is not None:
            raise ValueError("actions.stand_by.drive must be null")
        for name, effect in self.actions.items():
            if name != "stand_by" and effect.drive is None:
                raise ValueError(f"actions.{name}.drive must name a drive")
        return self


def load_personality(path: str | Path | None = None) -> Personality:
    """Load the thesis personality, overridden by the YAML file at ``path`` when given."""
    return load_model(Personality, "personality.yaml", path)
