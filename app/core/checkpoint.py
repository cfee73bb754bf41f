"""Atomic file writes: a crash mid-write never leaves a half-written checkpoint behind."""

from __future__ import annotations

import atexit
import contextlib
import os
import shutil
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any, BinaryIO

import torch

from app.core.errors import UserError


def atomic_write(path: str | Path, write: Callable[[BinaryIO], Any]) -> None:
    """Call ``write`` on a temporary file in the same folder, then rename it over ``path``."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        os.fchmod(fd, 0o644)  # mkstemp creates private files; checkpoints are ordinary ones
        with os.fdopen(fd, "wb") as fh:
            write(fh)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def atomic_write_bytes(path: str | Path, data: bytes) -> None:
    """Write ``data`` to ``path`` atomically."""
    atomic_write(path, lambda fh: fh.write(data))


def atomic_torch_save(obj: Any, path: str | Path) -> None:
    """``torch.save`` ``obj`` to ``path`` atomically."""
    atomic_write(path, lambda fh: torch.save(obj, fh))


def atomic_copy(src: str | Path, dst: str | Path) -> None:
    """Copy the file ``src`` to ``dst`` atomically (an exported model is whole or absent)."""
    with Path(src).open("rb") as source:
        atomic_write(dst, lambda fh: shutil.copyfileobj(source, fh))


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # alive, owned by another user
        pass
    return True


def claim_run_folder(out_dir: Path, checkpoint: Path, resume: bool) -> None:
    """Make ``out_dir`` this process's training folder. Refuse to start over an existing
    ``checkpoint`` unless resuming, and refuse a folder that another running process is
    training into: its ``.lock`` file holds that process id (a crashed run's stale lock is
    taken over), so two runs never interleave their logs and checkpoints. The lock is
    removed when this process exits."""
    out_dir.mkdir(parents=True, exist_ok=True)
    if checkpoint.exists() and not resume:
        raise FileExistsError(f"{checkpoint} exists: pass --resume to continue it, "
                              "or choose another --out")
    lock = out_dir / ".lock"
    try:
        owner = int(lock.read_text())
    except (OSError, ValueError):
        owner = None
    if owner is not None and owner != os.getpid() and _alive(owner):
        raise UserError(f"{out_dir}: process {owner} is training into this folder "
                        f"(stop it, or delete {lock} if it is not a training)")
    atomic_write_bytes(lock, str(os.getpid()).encode())
    atexit.register(_release, lock, os.getpid())


def _release(lock: Path, pid: int) -> None:
    """Remove ``lock`` if it still names ``pid`` (a forked child inherits the exit hook)."""
    with contextlib.suppress(OSError, ValueError):
        if int(lock.read_text()) == pid == os.getpid():
            lock.unlink()


def read_weights(path: str | Path, error: type[UserError], missing_hint: str) -> Any:
    """``torch.load`` a model file safely (``weights_only``), raising ``error`` with the path
    when the file is missing (adding ``missing_hint``) or unreadable."""
    path = Path(path)
    if not path.is_file():
        raise error(f"{path}: model file not found ({missing_hint})")
    try:
        return torch.load(path, map_location="cpu", weights_only=True)
    except Exception as exc:
        raise error(f"{path}: not a readable model file ({exc})") from None


def fp16_state(module: torch.nn.Module) -> dict[str, torch.Tensor]:
    """``module``'s state dict with floating-point tensors in fp16 (half the file size)."""
    return {k: v.half() if v.is_floating_point() else v for k, v in module.state_dict().items()}


def fp32_state(state: dict[str, torch.Tensor]) -> dict[str, torch.Tensor]:
    """A state dict written by :func:`fp16_state`, floating-point tensors back in fp32."""
    return {k: v.float() if v.is_floating_point() else v for k, v in state.items()}
