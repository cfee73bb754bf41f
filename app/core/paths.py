"""Where the project's own files live, so that no module counts parent folders itself."""

from __future__ import annotations

from pathlib import Path

REPO_ROOT = Path(__file__).resolve().parents[2]
DEFAULTS_DIR = REPO_ROOT / "app" / "defaults"   # packaged defaults of every config (thesis values)
MODELS_DIR = REPO_ROOT / "assets" / "models"    # shipped checkpoints and their model cards
URDF_DIR = REPO_ROOT / "assets" / "pepper_urdf"
WORLDS_DIR = REPO_ROOT / "worlds"
