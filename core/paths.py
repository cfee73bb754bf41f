"""Where the project's own files live, so that no module counts parent folders itself."""

from __future__ import annotations

from pathlib import Path

REPO_ROOT = Path(__file__).resolve().parents[1]
DEFAULTS_DIR = REPO_ROOT / "config"   # the defaults of every config (thesis values)
MODELS_DIR = REPO_ROOT / "assets" / "models"    # shipped checkpoints and their model cards
URDF_DIR = REPO_ROOT / "assets" / "pepper_urdf"
WORLDS_DIR = REPO_ROOT / "worlds"


def from_root(path: Path) -> Path:
    """A configured path: relative ones are taken from the repository root."""
    return path if path.is_absolute() else REPO_ROOT / path
