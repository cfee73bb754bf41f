"""Import ultralytics so that it never reaches for the network.

ultralytics checks for updates, installs missing packages, downloads fonts and pretrained
weights and sends analytics when it can. A companion robot runs offline and reproducibly,
so every entry point goes through :func:`ultralytics_module`, which switches those off
before the first import and keeps ultralytics' settings file out of the user's home.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path
from types import ModuleType

_ENV = {"YOLO_OFFLINE": "true", "YOLO_AUTOINSTALL": "false"}


def ultralytics_module(verbose: bool = False) -> ModuleType:
    """The ``ultralytics`` package, imported offline with its settings in a temp folder
    (``YOLO_CONFIG_DIR`` set by the user wins). ``verbose`` (read at the first import only)
    keeps its progress output. CPU training uses every core (ultralytics leaves one free)."""
    for key, value in _ENV.items():
        os.environ.setdefault(key, value)
    os.environ.setdefault("YOLO_VERBOSE", str(verbose).lower())
    os.environ.setdefault("YOLO_CONFIG_DIR",
                          str(Path(tempfile.gettempdir()) / "companion-ultralytics"))
    # imported here, after the environment above: ultralytics reads it at import time
    import ultralytics
    from ultralytics.utils import SETTINGS, torch_utils

    SETTINGS.update({"sync": False})
    torch_utils.NUM_THREADS = os.cpu_count() or 1
    return ultralytics
