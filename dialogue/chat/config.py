"""Schema of ``config/chat.yaml``: data mix, model sizes, training schedule, decoding,
reply ranking and follow-ups.

Every number that shapes the chit-chat model lives in that YAML file; a user file given with
``companion train chat --config FILE`` is deep-merged over it and unknown keys are errors.
"""

from __future__ import annotations

from pathlib import Path
from typing import Literal

from pydantic import Field, field_validator, model_validator

from core.config_files import StrictModel, load_model
from core.paths import MODELS_DIR, REPO_ROOT

DEFAULT_CHAT_MODEL = MODELS_DIR / "chat.pt"


class ChatDataConfig(StrictModel):
    """Where the conversations come from and how they become (input, reply) pairs."""

    papaya_dir: Path | None
    chatterbot: bool
    chatterbot_exclude: list[str]
    max_len: int = Field(ge=2)
    max_replies_per_input: int = Field(ge=1)
    min_count: int = Field(ge=1)
    split: tuple[float, float, float]
    seed: int
    max_pairs: int | None = Field(default=None, ge=3)  # total cap, shared out by ``split``

    @model_validator(mode="after")
    def _split_sums_to_one(self) -> ChatDataConfig:
        if min(self.split) <= 0 or abs(sum(self.split) - 1.0) > 1e-6:
            raise ValueError("split: three positive fractions summing to 1")
        return self

    def resolved_papaya(self) -> Path | None:
        """The Papaya folder; a relative path is taken from the repository root."""
        if self.papaya_dir is None:
            return None
        d = self.papaya_dir
        return d if d.is_absolute() else (REPO_ROOT / d).resolve()


class ChatModelConfig(StrictModel):
    """Sizes of the encoder-decoder (see docs/chitchat.md for the choice)."""

    embedding: int = Field(ge=1)
    hidden: int = Field(ge=2)
    layers: int = Field(ge=1)
    dropout: float = Field(ge=0, lt=1)
    bidirectional: bool

    @model_validator(mode="after")
    def _even_hidden(self) -> ChatModelConfig:
        if self.bidirectional and self.hidden % 2:
            raise ValueError("hidden: must be even for a bidirectional encoder")
        return self


class ChatTrainConfig(StrictModel):
    """The training schedule (Adam, teacher forcing, best validation perplexity kept)."""

    seed: int
    threads: int = Field(ge=1)
    epochs: int = Field(ge=1)
    batch_size: int = Field(ge=1)
    learning_rate: float = Field(gt=0)
    lr_decay: float = Field(gt=0, le=1)
    lr_patience: int = Field(ge=0)
    weight_decay: float = Field(ge=0)
    max_grad_norm: float | None = Field(default=None, gt=0)
    early_stop: int | None = Field(default=None, ge=1)
    checkpoint_every: int = Field(ge=1)
    log_every: int = Field(ge=1)


class ChatDecodeConfig(StrictModel):
    """Inference: beam search (or top-p sampling) with repetition control."""

    method: Literal["beam", "sample"]
    beam_size: int = Field(ge=1)
    max_len: int = Field(ge=1)
    min_len: int = Field(ge=0)
    length_penalty: float = Field(ge=0)
    no_repeat_ngram: int = Field(ge=0)
    top_p: float = Field(gt=0, le=1)
    temperature: float = Field(gt=0)
    seed: int | None = None


class ChatRankConfig(StrictModel):
    """Choosing a reply among beam and retrieved candidates (``dialogue/chat/rank.py``)."""

    enabled: bool
    retrieve: int = Field(ge=0)
    min_similarity: float = Field(ge=0, le=1)
    beam_candidates: int = Field(ge=1)
    model: float = Field(ge=0)
    match: float = Field(ge=0)
    topic: float = Field(ge=0)
    generic_penalty: float = Field(ge=0)
    generic: list[str]

    @field_validator("generic")
    @classmethod
    def _generic_has_words(cls, generic: list[str]) -> list[str]:
        empty = [g for g in generic if not any(c.isalnum() for c in g)]
        if empty:
            raise ValueError(f"replies without a word: {empty}")
        return generic


class ChatFollowUpConfig(StrictModel):
    """Lines that refer back to the person's earlier lines (``dialogue/chat/follow_up.py``)."""

    turns: int = Field(ge=0)
    max_words: int = Field(ge=0)
    female: list[str]
    male: list[str]

    @field_validator("female", "male")
    @classmethod
    def _single_lower_words(cls, words: list[str]) -> list[str]:
        bad = [w for w in words if not w.isalpha() or w != w.lower()]
        if bad:
            raise ValueError(f"single lower-case words only, not {bad}")
        return words


class ChatConfig(StrictModel):
    """Everything ``companion train chat`` needs, and how the robot picks its replies."""

    data: ChatDataConfig
    model: ChatModelConfig
    train: ChatTrainConfig
    decode: ChatDecodeConfig
    rank: ChatRankConfig
    follow_up: ChatFollowUpConfig


def load_chat_config(path: str | Path | None = None) -> ChatConfig:
    """Load ``config/chat.yaml``, overridden by the YAML file at ``path`` when given."""
    return load_model(ChatConfig, "chat.yaml", path)
