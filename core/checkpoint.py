"""Atomic file writes (a crash mid-write never leaves a half-written checkpoint behind), safe
model-file reading, and :class:`TrainingFolder`, the one checkpoint/resume helper of the
project's own trainers (policy, chit-chat, facing, and through :mod:`textnets.loop` style
transfer and VQG; ultralytics keeps its own for the detector)."""

from __future__ import annotations

import atexit
import contextlib
import csv
import io
import os
import shutil
import tempfile
import time
import zipfile
from collections.abc import Callable
from pathlib import Path
from typing import IO, Any, BinaryIO, NoReturn

import numpy as np
import torch
from pydantic import BaseModel

from core.errors import UserError
from core.run_config import CHECKPOINT_FILE, refuse_changes, stored_config, write_config


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
    removed when this process exits. Temporary files that a killed writer left behind
    (:func:`atomic_write`'s ``.*.tmp``) are removed."""
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
    for tmp in out_dir.glob(".*.tmp"):  # left by a writer killed mid-write (SIGKILL)
        tmp.unlink(missing_ok=True)


def _release(lock: Path, pid: int) -> None:
    """Remove ``lock`` if it still names ``pid`` (a forked child inherits the exit hook)."""
    with contextlib.suppress(OSError, ValueError):
        if int(lock.read_text()) == pid == os.getpid():
            lock.unlink()


def _unreadable(path: Path, exc: Exception) -> str:
    """Why ``torch.load`` failed on ``path``, in a few words on one line."""
    if not path.is_file():
        return "not a file"
    if path.stat().st_size == 0:
        return "the file is empty"
    if not zipfile.is_zipfile(path):
        return "cut short, or not written by torch.save"
    first = str(exc).strip().split("\n")[0].split(". ")[0][:100]
    return f"{type(exc).__name__}: {first}"


def read_weights(path: str | Path, error: type[UserError], missing_hint: str) -> Any:
    """``torch.load`` a model file safely (``weights_only``), raising ``error`` with the path
    when the file is missing (adding ``missing_hint``) or unreadable."""
    path = Path(path)
    if not path.is_file():
        raise error(f"{path}: model file not found ({missing_hint})")
    try:
        return torch.load(path, map_location="cpu", weights_only=True)
    except Exception as exc:
        raise error(f"{path}: not a readable model file ({_unreadable(path, exc)})") from None


def fp16_state(module: torch.nn.Module) -> dict[str, torch.Tensor]:
    """``module``'s state dict with floating-point tensors in fp16 (half the file size)."""
    return {k: v.half() if v.is_floating_point() else v for k, v in module.state_dict().items()}


def fp32_state(state: dict[str, torch.Tensor]) -> dict[str, torch.Tensor]:
    """A state dict written by :func:`fp16_state`, floating-point tensors back in fp32."""
    return {k: v.float() if v.is_floating_point() else v for k, v in state.items()}


_ARRAY = "numpy.ndarray"  # marks an array stored as a tensor in a checkpoint


def _pack(obj: Any) -> Any:
    """``obj`` with numpy arrays as marked tensors and numpy scalars as Python numbers, so that
    a checkpoint loads with ``weights_only=True`` (no pickled code)."""
    if isinstance(obj, np.ndarray):
        return (_ARRAY, torch.from_numpy(obj))
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, dict):
        return {k: _pack(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return type(obj)(_pack(v) for v in obj)
    return obj


def _unpack(obj: Any) -> Any:
    """The inverse of :func:`_pack`."""
    if isinstance(obj, tuple) and len(obj) == 2 and obj[0] == _ARRAY:
        return obj[1].numpy()
    if isinstance(obj, dict):
        return {k: _unpack(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return type(obj)(_unpack(v) for v in obj)
    return obj


class Checkpoint(dict):
    """A loaded checkpoint; an entry it lacks raises the training's error naming the file
    (one written by another training or an older version)."""

    def __init__(self, state: dict[str, Any], path: Path, error: type[UserError]) -> None:
        super().__init__(state)
        self.path, self.error = path, error

    def __missing__(self, key: str) -> NoReturn:
        raise self.error(f"{self.path}: holds no {key!r} (written by another training or an "
                         "older version); train into a new --out folder")


def read_checkpoint(path: Path, error: type[UserError] = UserError) -> Checkpoint:
    """A training checkpoint written by :meth:`TrainingFolder.save`, loaded with
    ``weights_only=True``; ``error`` names the file, in one line, when it cannot be read."""
    try:
        state = _unpack(torch.load(path, map_location="cpu", weights_only=True))
    except Exception as exc:
        why = _unreadable(path, exc)
    else:
        if isinstance(state, dict):
            return Checkpoint(state, path, error)
        why = f"it holds a {type(state).__name__}"
    raise error(f"{path}: not a readable checkpoint ({why}); delete it to start the run "
                "over, or train into a new --out folder")


class TrainingFolder:
    """The folder of one training run and its resumable ``checkpoint.pt``.

    The folder is claimed (:func:`claim_run_folder`); an existing checkpoint is loaded with
    ``weights_only=True`` (:attr:`state`, None on a fresh run) and refused with ``error`` when
    unreadable; :meth:`save` writes it atomically with the training's wall time so far, which
    :meth:`wall` carries across resumes. :meth:`use_config` stores the configuration of a
    fresh run and holds a resumed one to it (:mod:`core.run_config`); :meth:`restore`
    loads state dicts from the checkpoint. :meth:`open_log` starts each CSV log with its
    header on a fresh run; on a resumed one the log keeps the rows up to the checkpoint.
    """

    def __init__(self, out_dir: Path, resume: bool, error: type[UserError] = UserError) -> None:
        self.out_dir, self.resume, self.error = out_dir, resume, error
        self.ckpt_path = out_dir / CHECKPOINT_FILE
        claim_run_folder(out_dir, self.ckpt_path, resume)
        self.state: Checkpoint | None = None
        if self.ckpt_path.exists():
            self.state = read_checkpoint(self.ckpt_path, error)
        self._wall_offset = float(self.state["wall_s"]) if self.state else 0.0
        self._start = time.perf_counter()

    def wall(self) -> float:
        """Seconds of training so far, across resumes."""
        return self._wall_offset + time.perf_counter() - self._start

    def save(self, state: dict[str, Any]) -> None:
        """Write the checkpoint atomically (``state`` plus ``wall_s``)."""
        atomic_torch_save(_pack({**state, "wall_s": self.wall()}), self.ckpt_path)

    def use_config(self, config: BaseModel) -> None:
        """Train with ``config``: a fresh run stores it as ``resolved_config.yaml``; a resumed
        run refuses it where it differs from the stored one."""
        stored = (stored_config(type(config), self.out_dir, self.error) if self.resume
                  else None)
        if stored is None:
            write_config(self.out_dir, config)
        else:
            refuse_changes(self.out_dir, stored, config, "the configuration given has",
                           self.error)

    def restore(self, **targets: Any) -> None:
        """Load each target's ``load_state_dict`` from the checkpoint entry of its name, or
        raise the folder's error saying that this checkpoint cannot be resumed."""
        assert self.state is not None
        for key, target in targets.items():
            try:
                target.load_state_dict(self.state[key])
            except (KeyError, RuntimeError, ValueError, TypeError) as exc:
                why = str(exc).strip().split("\n")[0]
                raise self.error(
                    f"{self.ckpt_path}: cannot resume from this checkpoint, written for another "
                    f"configuration or by an older version ({key}: {type(exc).__name__}: "
                    f"{why}); train into a new --out folder") from None

    def open_log(self, name: str, header: list[str],
                 keep: Callable[[list[str]], bool]) -> IO[str]:
        """The CSV log ``name`` opened for appending rows. A fresh run (no checkpoint) starts
        it with ``header``; a resumed one keeps the earlier rows that ``keep`` accepts (those
        up to the checkpoint) and drops the rest, and any row cut short or unparsable."""
        path = self.out_dir / name
        rows: list[list[str]] = []
        if self.state is not None and path.exists():
            with path.open(newline="") as fh:
                rows = [r for r in list(csv.reader(fh))[1:] if _kept(r, len(header), keep)]
        text = io.StringIO()
        csv.writer(text).writerows([header, *rows])
        atomic_write_bytes(path, text.getvalue().encode())  # a kill now loses no kept row
        return path.open("a", newline="")


def _kept(row: list[str], width: int, keep: Callable[[list[str]], bool]) -> bool:
    """Whether a resumed log keeps ``row``: whole (``width`` fields), parsable, and ``keep``."""
    try:
        return len(row) == width and keep(row)
    except ValueError:
        return False
