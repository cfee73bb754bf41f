"""Schema of ``config/tablet.yaml``: the tablet's server, buttons, live view and replay."""

from __future__ import annotations

from pathlib import Path
from typing import Self

from pydantic import Field, model_validator

from core.config_files import StrictModel, load_model
from dialogue.intent import CHITCHAT
from dialogue.qa import CATEGORIES

KINDS = (CHITCHAT, *CATEGORIES)   # the conversation kinds of thesis Table 3.4


class ServerConfig(StrictModel):
    """Where the pages are served and what a request may cost."""

    host: str = Field(min_length=1, max_length=253)
    port: int = Field(ge=0, le=65535)
    max_body_bytes: int = Field(ge=64, le=1_000_000)
    max_queued: int = Field(ge=1, le=10_000)
    reply_timeout_s: float = Field(gt=0, le=600)


class Button(StrictModel):
    """One conversation kind's button: its label and the line its press says."""

    label: str = Field(min_length=1, max_length=40)
    line: str = Field(min_length=1, max_length=200)


class LiveConfig(StrictModel):
    """How often and how richly the live view is refreshed during a run."""

    snapshot_hz: float = Field(gt=0, le=30)
    frame_width: int = Field(ge=32, le=1280)
    jpeg_quality: int = Field(ge=1, le=100)
    dialogue_lines: int = Field(ge=1, le=200)


class ReplayConfig(StrictModel):
    """What a run keeps for ``companion view``."""

    frame_period_s: float = Field(gt=0, le=3600)
    max_frames: int = Field(ge=0, le=100_000)


class TabletConfig(StrictModel):
    """The whole of ``tablet.yaml``."""

    server: ServerConfig
    person: str = Field(min_length=1, max_length=60)
    buttons: dict[str, Button]
    live: LiveConfig
    replay: ReplayConfig

    @model_validator(mode="after")
    def _every_kind(self) -> Self:
        if set(self.buttons) != set(KINDS):
            raise ValueError(f"buttons must name exactly these kinds: {', '.join(KINDS)}")
        return self


def load_tablet_config(path: str | Path | None = None) -> TabletConfig:
    """The default tablet config, overridden by the YAML file at ``path`` when given."""
    return load_model(TabletConfig, "tablet.yaml", path)
