"""Schema of ``config/policy.yaml``: the training environment, network and DQN."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Self

from pydantic import Field, model_validator

from core.config_files import StrictModel, load_model
from core.paths import MODELS_DIR
from mind.personality import Action, Motivation

DriveLevel = Annotated[float, Field(ge=0, le=1)]
DriveRange = tuple[DriveLevel, DriveLevel]


def check_order(name: str, bounds: DriveRange | None) -> None:
    """Reject a ``[low, high]`` range whose low end lies above its high end."""
    if bounds is not None and bounds[0] > bounds[1]:
        raise ValueError(f"{name}: lower bound {bounds[0]} exceeds upper bound {bounds[1]}")


class PeopleConfig(StrictModel):
    """People coming and going in front of the robot."""

    arrive_prob: float = Field(ge=0, le=1)
    leave_prob: float = Field(ge=0, le=1)
    find_success_prob: float = Field(ge=0, le=1)


class EncouragementConfig(StrictModel):
    """Praise from a person after a social action."""

    after_actions: list[Action]
    prob: float = Field(ge=0, le=1)
    duration: int = Field(ge=1)


class HeatConfig(StrictModel):
    """A first-order motor heat model that raises the overheat stimulus."""

    threshold: float = Field(gt=0, le=1)
    initial: tuple[float, float]
    heating: dict[Action, float]
    cooling: dict[Action, float]
    other_cooling: float = Field(ge=0, le=1)


class EnvConfig(StrictModel):
    """The abstract household the policy trains in."""

    episode_steps: int = Field(ge=1)
    terminate_on_insecure: bool
    initial_drives: DriveRange
    people: PeopleConfig
    encouragement: EncouragementConfig
    heat: HeatConfig

    @model_validator(mode="after")
    def _ordered(self) -> Self:
        check_order("initial_drives", self.initial_drives)
        return self


class NetworkConfig(StrictModel):
    """Sizes of the dueling Q-network."""

    hidden: list[int] = Field(min_length=1)
    head: int = Field(ge=1)
    init_std: float = Field(gt=0)
    input_offset: float = 0.0
    input_scale: float = Field(default=1.0, gt=0)


class TrainConfig(StrictModel):
    """Dueling Double DQN hyper-parameters (thesis §4.1 where it gives them)."""

    seed: int
    num_envs: int = Field(ge=1)
    episode_steps: int = Field(ge=1)
    terminate_on_insecure: bool
    insecure_penalty: float = Field(default=0.0, le=0)
    time_cost: float = Field(default=0.0, ge=0)
    total_transitions: int = Field(ge=1)
    gamma: float = Field(ge=0, le=1)
    gamma_steps: int | None = Field(default=None, ge=1)
    n_step: int = Field(default=1, ge=1)
    learning_rate: float = Field(gt=0)
    learning_rate_end: float | None = Field(default=None, gt=0)
    rmsprop_alpha: float = Field(gt=0, lt=1)
    rmsprop_eps: float = Field(gt=0)
    buffer_size: int = Field(ge=1)
    batch_size: int = Field(ge=1)
    learning_starts: int = Field(ge=0)
    updates_per_transition: float = Field(gt=0)
    target_sync_updates: int = Field(ge=1)
    epsilon_start: float = Field(ge=0, le=1)
    epsilon_end: float = Field(ge=0, le=1)
    exploration_fraction: float = Field(gt=0, le=1)
    max_grad_norm: float | None = Field(default=None, gt=0)
    checkpoint_every: int = Field(ge=1)
    eval_every: int = Field(ge=1)
    eval_episodes: int = Field(ge=1)
    eval_seed: int
    select_rsr: float = Field(ge=0, le=1)
    demo_transitions: int = Field(default=0, ge=0)
    demo_seed: int = 200000
    demo_past_insecure: bool = False
    demo_initial_drives: DriveRange | None = None
    demo_pretrain_updates: int = Field(default=0, ge=0)
    demo_share: float = Field(default=0.25, ge=0, le=1)
    demo_weight: float = Field(default=1.0, ge=0)
    demo_weight_rl: float | None = Field(default=None, ge=0)
    demo_margin: float = Field(default=0.8, ge=0)
    demo_anticipation: dict[Motivation, Annotated[float, Field(ge=0, le=1)]] = Field(
        default_factory=dict)

    @model_validator(mode="after")
    def _ordered(self) -> Self:
        check_order("demo_initial_drives", self.demo_initial_drives)
        return self


class PolicyConfig(StrictModel):
    """Everything ``companion train policy`` needs besides the personality."""

    env: EnvConfig
    network: NetworkConfig
    train: TrainConfig


def load_policy_config(path: str | Path | None = None) -> PolicyConfig:
    """Load the default policy config, overridden by the YAML file at ``path`` when given."""
    return load_model(PolicyConfig, "policy.yaml", path)


DEFAULT_POLICY = MODELS_DIR / "policy.pt"
