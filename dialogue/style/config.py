"""Schema of ``config/style.yaml``: data split, model sizes, training schedule, decoding.

Every number that shapes the style-transfer system lives in that YAML file; a user file given
with ``--config`` is deep-merged over it and unknown keys are errors.
"""

from __future__ import annotations

from pathlib import Path

from pydantic import Field, model_validator

from core.config_files import StrictModel, load_model
from core.paths import MODELS_DIR, REPO_ROOT


class DataConfig(StrictModel):
    """Where the Yelp files are and how they are re-split and tokenised."""

    dir: Path
    negative: list[str] = Field(min_length=1)
    positive: list[str] = Field(min_length=1)
    split: tuple[float, float, float]
    seed: int
    dedupe: bool
    max_words: int = Field(ge=1)
    min_count: int = Field(ge=1)
    max_per_class: int | None = Field(default=None, ge=3)

    @model_validator(mode="after")
    def _split_sums_to_one(self) -> DataConfig:
        if min(self.split) <= 0 or abs(sum(self.split) - 1.0) > 1e-6:
            raise ValueError("split: three positive fractions summing to 1")
        return self

    def resolved_dir(self) -> Path:
        """The data folder; a relative path is taken from the repository root."""
        return self.dir if self.dir.is_absolute() else (REPO_ROOT / self.dir).resolve()


class ModelConfig(StrictModel):
    """Sizes of E_y, E_z, G and the N+1 discriminator.

    E_z and G both have ``style_dim + content_dim`` hidden units: E_z starts from
    ``[y, 0]`` and G from ``[z, y]``.
    """

    embed_dim: int = Field(ge=1)
    style_dim: int = Field(ge=1)
    content_dim: int = Field(ge=1)
    style_autoencoder: bool
    style_hidden: int = Field(ge=1)
    disc_filters: int = Field(ge=1)
    disc_kernels: list[int] = Field(min_length=1)
    disc_dropout: float = Field(ge=0, lt=1)
    mask_ratio: float | None = Field(default=None, gt=1)
    mask_min_count: int = Field(default=10, ge=1)
    attention: bool = False


class ClassifierConfig(StrictModel):
    """The TextCNN sentiment classifier used to measure transfer accuracy."""

    embed_dim: int = Field(ge=1)
    filters: int = Field(ge=1)
    kernels: list[int] = Field(min_length=1)
    dropout: float = Field(ge=0, lt=1)
    epochs: float = Field(gt=0)
    batch_size: int = Field(ge=1)
    lr: float = Field(gt=0)


class LMConfig(StrictModel):
    """The LSTM language model that measures fluency (perplexity)."""

    embed_dim: int = Field(ge=1)
    hidden: int = Field(ge=1)
    dropout: float = Field(ge=0, lt=1)
    epochs: float = Field(gt=0)
    batch_size: int = Field(ge=1)
    lr: float = Field(gt=0)


class LossWeights(StrictModel):
    """Weights of the generator-side losses (§4.2: 1 / 1 / 0.3)."""

    style: float = Field(ge=0)
    rec: float = Field(ge=0)
    adv: float = Field(ge=0)
    cycle: float = Field(ge=0)
    per_word: bool = False   # rec and cycle per word instead of summed over the sentence


class GumbelConfig(StrictModel):
    """Gumbel-softmax temperature: tau_start * decay ** (step // every), floored at tau_min."""

    tau_start: float = Field(gt=0, le=1)
    decay: float = Field(gt=0, le=1)
    every: int = Field(ge=1)
    tau_min: float = Field(gt=0, le=1)


class TrainConfig(StrictModel):
    """Schedule of the pre-training and adversarial phases."""

    seed: int
    threads: int = Field(ge=1)
    batch_size: int = Field(ge=1)
    pretrain_lr: float = Field(gt=0)
    lr: float = Field(gt=0)
    disc_lr: float = Field(gt=0)
    betas: tuple[float, float]
    grad_clip: float = Field(gt=0)
    lm_steps: int = Field(ge=0)
    rec_steps: int = Field(ge=0)
    adversarial_steps: int = Field(ge=0)
    generator_steps_per_disc: int = Field(ge=1)
    weights: LossWeights
    gumbel: GumbelConfig
    log_every: int = Field(ge=1)
    checkpoint_every: int = Field(ge=1)
    eval_every: int = Field(ge=1)
    eval_sentences: int = Field(ge=1)
    select_min_bleu: float = Field(ge=0, le=100)


class DecodeConfig(StrictModel):
    """Inference: beam search, the checks before decoding and the content-preservation
    confidence check. ``max_words`` (twice the training limit ``data.max_words``) and
    ``min_known_share`` have defaults because the model files written before they existed do
    not store them."""

    beam_size: int = Field(ge=1)
    max_extra_words: int = Field(ge=0)
    disc_weight: float = Field(ge=0)
    max_words: int = Field(default=30, ge=1, le=1000)
    min_known_share: float = Field(default=0.5, ge=0, le=1)
    min_content_overlap: float = Field(ge=0, le=1)
    style_ratio: float = Field(ge=1)
    style_min_count: int = Field(ge=1)


class ConversationConfig(StrictModel):
    """Conversational lines added to the training split of the transfer model (not of its
    judges), each labelled by the sentiment judge; see docs/style_transfer.md."""

    chat: bool = False       # the chit-chat TRAIN split's replies (config/chat.yaml)
    qa: bool = False         # the QA bot's answers to the intent training questions
    repeat: int = Field(default=1, ge=1)   # each line this many times in the training set
    min_confidence: float = Field(default=0.5, ge=0.5, lt=1)   # the judge's, to keep a line
    max_words: int = Field(default=15, ge=1)


class StyleConfig(StrictModel):
    """Everything ``companion train style`` needs."""

    data: DataConfig
    conversation: ConversationConfig = ConversationConfig()
    model: ModelConfig
    classifier: ClassifierConfig
    lm: LMConfig
    train: TrainConfig
    decode: DecodeConfig


def load_style_config(path: str | Path | None = None) -> StyleConfig:
    """Load ``config/style.yaml``, overridden by the YAML file at ``path`` when given."""
    return load_model(StyleConfig, "style.yaml", path)


DEFAULT_MODEL_DIR = MODELS_DIR / "style"
STYLE_FILE, CLASSIFIER_FILE, LM_FILE = "style.pt", "classifier.pt", "lm.pt"
