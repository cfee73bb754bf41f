"""Schema of ``config/conversation.yaml``: where the robot's everyday knowledge lies and
how it checks a heard line before answering it."""

from __future__ import annotations

from functools import cache
from pathlib import Path

from pydantic import Field

from core.config_files import StrictModel, load_model


class KnowledgeConfig(StrictModel):
    """The offline knowledge sources."""

    wordnet_dir: Path


class InputCheckConfig(StrictModel):
    """When a line is too long, not understood or not English (``dialogue/input_check.py``)."""

    max_words: int = Field(ge=1)
    min_known_share: float = Field(ge=0, le=1)
    max_foreign_letters: float = Field(ge=0, le=1)
    extra_words: list[str]


class PersonaConfig(StrictModel):
    """Who the robot says it is (``dialogue/persona.py``)."""

    name: str = Field(min_length=1)
    kind: str = Field(min_length=1)
    likes: list[str] = Field(min_length=1)


class AddresseeConfig(StrictModel):
    """How the robot tells whom a line is said to (``dialogue/addressee.py``)."""

    robot_words: list[str]
    group_words: list[str]
    family_words: list[str]
    openers: list[str] = Field(min_length=1)
    first_words: int = Field(ge=1)


class ConversationConfig(StrictModel):
    """The whole file."""

    knowledge: KnowledgeConfig
    input_check: InputCheckConfig
    persona: PersonaConfig
    addressee: AddresseeConfig


@cache
def load_conversation_config(path: str | Path | None = None) -> ConversationConfig:
    """The packaged defaults, merged with a user's file at ``path``."""
    return load_model(ConversationConfig, "conversation.yaml", path)
