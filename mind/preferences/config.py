"""Schema of ``config/feedback.yaml``: adaptation to feedback and simulated users."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Self

from pydantic import Field, model_validator

from core.config_files import StrictModel, load_model
from mind.personality import Action

Probability = Annotated[float, Field(ge=0, le=1)]


class AdaptationConfig(StrictModel):
    """How the robot turns feedback into choices (docs/feedback.md)."""

    learning_rate: float = Field(gt=0, le=1)
    weight_disliked: float = Field(ge=0, le=1000)
    weight_liked: float = Field(ge=0, le=1000)
    safety_margin: float = Field(ge=0, le=1)
    credit_window_s: float = Field(gt=0, le=3600)
    person_window_s: float = Field(gt=0, le=86400)

    @property
    def weights(self) -> tuple[float, float]:
        """``(weight_disliked, weight_liked)``."""
        return self.weight_disliked, self.weight_liked


class SpokenConfig(StrictModel):
    """Praise and scolding heard in what people say."""

    threshold: float = Field(gt=0, le=1)


class Reaction(StrictModel):
    """Chances of praise and of scolding when a user reacts to an action."""

    praise: Probability
    scold: Probability

    @model_validator(mode="after")
    def _at_most_one(self) -> Self:
        if self.praise + self.scold > 1:
            raise ValueError("praise + scold must be at most 1")
        return self


class TasteLists(StrictModel):
    """Actions someone likes and dislikes (never both); simulated users and scenario people
    have them."""

    likes: tuple[Action, ...] = ()
    dislikes: tuple[Action, ...] = ()

    @model_validator(mode="after")
    def _disjoint(self) -> Self:
        both = set(self.likes) & set(self.dislikes)
        if both:
            raise ValueError(f"liked and disliked at once: {sorted(both)}")
        return self


class UserType(TasteLists):
    """One kind of simulated user: their share of the population and their tastes."""

    share: Probability


class SimulatedUsers(StrictModel):
    """The population of hidden preferences that ``companion eval feedback`` adapts to."""

    react_prob: Probability
    liked: Reaction
    disliked: Reaction
    neutral: Reaction
    unseen: tuple[Action, ...] = ()
    types: dict[str, UserType] = Field(min_length=1)

    @model_validator(mode="after")
    def _shares(self) -> Self:
        total = sum(t.share for t in self.types.values())
        if abs(total - 1.0) > 1e-6:
            raise ValueError(f"the shares of the user types sum to {total:g}, not 1")
        return self


class FeedbackConfig(StrictModel):
    """Everything about feedback: the robot's adaptation and the simulated users."""

    adaptation: AdaptationConfig
    spoken: SpokenConfig
    simulated_users: SimulatedUsers


def load_feedback_config(path: str | Path | None = None) -> FeedbackConfig:
    """The default feedback config, overridden by the YAML file at ``path`` when given."""
    return load_model(FeedbackConfig, "feedback.yaml", path)
