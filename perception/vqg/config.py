"""Schema of ``config/vqg.yaml``: data, model sizes, training schedule and decoding.

Every number that shapes the visual question generator lives in that YAML file; a user file
given with ``--config`` is deep-merged over it and unknown keys are errors.
"""

from __future__ import annotations

from pathlib import Path
from typing import Literal, Self

from pydantic import Field, PositiveInt, model_validator

from core.config_files import StrictModel, load_model
from core.paths import MODELS_DIR, REPO_ROOT

DEFAULT_VERIFIER = MODELS_DIR / "vqg_verifier.pt"  # perception/vqg/verify.py
ABLATIONS = ("no_d1", "no_d2", "gaussian")


class DataConfig(StrictModel):
    """Where the data set is and how its images and questions become tensors."""

    dir: Path
    image_width: PositiveInt
    image_height: PositiveInt
    max_words: PositiveInt
    min_count: PositiveInt

    def resolved_dir(self) -> Path:
        """The data folder; a relative path is taken from the repository root."""
        return self.dir if self.dir.is_absolute() else (REPO_ROOT / self.dir).resolve()


class ModelConfig(StrictModel):
    """Sizes of E_I, E_z, the latent, G, D1 and D2 (thesis Figs. 3.16-3.20).

    E_z has ``feature_dim`` units (its initial state is the image feature f); G has
    ``latent_vars * latent_classes + feature_dim`` units (initial state ``[z, f]``); D2's
    LSTM has ``feature_dim`` units (its last state is dotted with f).
    """

    blocks: list[list[PositiveInt]] = Field(min_length=1)
    pool_grid: tuple[PositiveInt, PositiveInt]
    feature_dim: PositiveInt
    image_dropout: float = Field(ge=0, lt=1)
    embed_dim: PositiveInt
    latent: Literal["gumbel", "gaussian"]
    latent_vars: PositiveInt
    latent_classes: int = Field(ge=2)
    word_dropout: float = Field(ge=0, lt=1)
    use_d1: bool
    use_d2: bool
    d1_filters: PositiveInt
    d1_kernels: list[PositiveInt] = Field(min_length=1)
    d1_dropout: float = Field(ge=0, lt=1)
    d2_channels: PositiveInt
    d2_kernel: PositiveInt

    @property
    def latent_dim(self) -> int:
        """Width of the latent code z."""
        return self.latent_vars * self.latent_classes


class LossWeights(StrictModel):
    """Weights of eqs. 3.16-3.18 (§4.3: all 1)."""

    rec: float = Field(ge=0)
    kl: float = Field(ge=0)
    g1: float = Field(ge=0)
    g2: float = Field(ge=0)
    d1: float = Field(ge=0)
    d2: float = Field(ge=0)
    d2_mismatch: float = Field(ge=0)


class GumbelConfig(StrictModel):
    """Temperature: tau_start * decay ** (step // every), floored at tau_min."""

    tau_start: float = Field(gt=0, le=1)
    decay: float = Field(gt=0, le=1)
    every: PositiveInt
    tau_min: float = Field(gt=0, le=1)


class TrainConfig(StrictModel):
    """The three phases: image encoder, VAE reconstruction, adversarial training."""

    seed: int
    threads: PositiveInt
    image_batch: PositiveInt
    image_steps: int = Field(ge=0)
    image_lr: float = Field(gt=0)
    weight_decay: float = Field(ge=0)
    image_targets: tuple[Literal["words", "facts"], ...] = Field(min_length=1)
    image_fact_min_images: PositiveInt
    batch_size: PositiveInt
    vae_steps: int = Field(ge=0)
    adversarial_steps: int = Field(ge=0)
    lr: float = Field(gt=0)
    adv_lr: float = Field(gt=0)
    disc_lr: float = Field(gt=0)
    betas: tuple[float, float]
    grad_clip: float = Field(gt=0)
    kl_warmup_steps: int = Field(ge=0)
    kl_free_nats: float = Field(ge=0)
    generator_steps_per_disc: PositiveInt
    weights: LossWeights
    gumbel: GumbelConfig
    log_every: PositiveInt
    checkpoint_every: PositiveInt
    eval_every: PositiveInt
    select_images: PositiveInt
    select_samples: PositiveInt


class DecodeConfig(StrictModel):
    """Inference: latents drawn per requested question, greedy or sampled words, and the
    two checks on what was decoded (the generator's confidence, the fact verifier)."""

    oversample: PositiveInt
    greedy: bool
    temperature: float = Field(gt=0)
    max_words: PositiveInt
    min_logprob: float
    fact_check: bool
    verifier: Path | None = None
    min_fact_prob: float = Field(ge=0, le=1)

    def verifier_path(self) -> Path | None:
        """The fact verifier to load: ``verifier``, or the shipped one; None when
        ``fact_check`` is off."""
        if not self.fact_check:
            return None
        return DEFAULT_VERIFIER if self.verifier is None else self.verifier


class EvalConfig(StrictModel):
    """`companion eval vqg` defaults and the bars of the issue."""

    images: PositiveInt
    samples: PositiveInt
    latency_runs: PositiveInt
    latency_n: PositiveInt
    ablation_scale: float = Field(gt=0, le=1)
    bars: dict[str, float]
    household_bars: dict[str, float]


class VqgConfig(StrictModel):
    """Everything ``companion train vqg`` and ``companion eval vqg`` need."""

    data: DataConfig
    model: ModelConfig
    train: TrainConfig
    decode: DecodeConfig
    eval: EvalConfig

    @model_validator(mode="after")
    def _consistent(self) -> Self:
        if self.train.gumbel.tau_min > self.train.gumbel.tau_start:
            raise ValueError("train.gumbel.tau_min: above tau_start")
        if 2 ** len(self.model.blocks) > min(self.data.image_width, self.data.image_height):
            raise ValueError("model.blocks: too many pooling stages for the image size")
        return self

    def ablated(self, name: str | None) -> VqgConfig:
        """This config with one ablation of :data:`ABLATIONS` switched on (None: unchanged)."""
        if name is None:
            return self
        if name not in ABLATIONS:
            raise ValueError(f"unknown ablation {name!r} (choose from {', '.join(ABLATIONS)})")
        update = {"no_d1": {"use_d1": False}, "no_d2": {"use_d2": False},
                  "gaussian": {"latent": "gaussian"}}[name]
        return self.model_copy(update={"model": self.model.model_copy(update=update)})


def load_vqg_config(path: str | Path | None = None) -> VqgConfig:
    """Load ``config/vqg.yaml``, overridden by the YAML file at ``path`` when given."""
    return load_model(VqgConfig, "vqg.yaml", path)
