"""The folder of one household run, claimed for the run's lifetime.

:func:`claim` makes ``out`` this process's run folder or refuses with a
:class:`~core.errors.UserError`:

- another live process holding the folder's ``.lock`` (an ``flock``, so the kernel frees it
  when that process dies, even by SIGKILL) is refused: two runs never interleave their files;
- a folder that holds an earlier run is refused unless ``overwrite``, which clears it first
  (only the run's own files go: a folder holding anything else is never cleared);
- a folder the process cannot create or write names the folder and the reason.

:func:`default_folder` gives a fresh ``runs/<scenario>-<YYYYmmdd-HHMMSS>`` folder.
"""

from __future__ import annotations

import fcntl
import os
import shutil
import time
from pathlib import Path

from core.errors import UserError

LOCK = ".lock"
# Files and folders a household run writes; a folder with only these (and the lock) is a run.
RUN_FILES = {"events.jsonl", "timeline.csv", "dialogue.jsonl", "metrics.json", "tree.txt",
             "scenario.yaml", "plots", "frames", "audio", "view"}
RUN_MARKERS = {"events.jsonl", "metrics.json", "scenario.yaml"}
_held: dict[Path, int] = {}   # folder -> lock file descriptor, kept open while the run lives


class RunFolderError(UserError):
    """The run folder cannot be used; the message says why and what to do."""


def _run_file(name: str) -> bool:
    """Whether a run writes entries called ``name`` (maps it drew; temporary files)."""
    return name in RUN_FILES or name.startswith((".", "map_"))


def default_folder(root: Path, name: str) -> Path:
    """``root/<name>-<timestamp>``, with a counter appended when that exists already."""
    stamp = time.strftime("%Y%m%d-%H%M%S")
    folder, n = root / f"{name}-{stamp}", 1
    while folder.exists():
        n += 1
        folder = root / f"{name}-{stamp}-{n}"
    return folder


def lock_folder(out: Path) -> int:
    """Take the folder's ``.lock`` (an ``flock`` held while the returned descriptor is
    open) or raise :class:`RunFolderError` naming the process that holds it."""
    path = out / LOCK
    try:
        fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
    except OSError as exc:
        raise RunFolderError(f"{out}: cannot write into this folder ({exc.strerror})") from None
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        owner = os.pread(fd, 32, 0).decode(errors="replace").strip() or "?"
        os.close(fd)
        raise RunFolderError(f"{out}: process {owner} is running into this folder "
                             "(wait for it, or choose another --out)") from None
    os.ftruncate(fd, 0)
    os.pwrite(fd, f"{os.getpid()}\n".encode(), 0)
    return fd


def _clear(out: Path, entries: list[Path]) -> None:
    for entry in entries:
        if entry.is_dir() and not entry.is_symlink():
            shutil.rmtree(entry)
        else:
            entry.unlink()


def claim(out: Path, overwrite: bool = False) -> None:
    """Make ``out`` this process's run folder (see the module docstring)."""
    out = Path(out)
    if out in _held:
        return
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise RunFolderError(f"{out}: cannot create the run folder ({exc.strerror})") from None
    fd = lock_folder(out)
    entries = [e for e in out.iterdir() if e.name != LOCK]
    names = {e.name for e in entries}
    try:
        if names and not names & RUN_MARKERS:
            raise RunFolderError(f"{out}: the folder is not empty and holds no run; "
                                 "choose another --out")
        if names and not overwrite:
            raise RunFolderError(f"{out} holds an earlier run: pass --overwrite to replace "
                                 "it, or choose another --out")
        foreign = sorted(n for n in names if not _run_file(n))
        if foreign:
            raise RunFolderError(f"{out}: --overwrite clears only a run's own files, and "
                                 f"this folder also holds {', '.join(foreign[:3])}")
        _clear(out, entries)
    except BaseException:
        (out / LOCK).unlink(missing_ok=True)   # held by this process: nobody else uses it
        os.close(fd)
        raise
    _held[out] = fd


def release(out: Path) -> None:
    """Give the folder's lock back (the kernel does it too when the process ends)."""
    fd = _held.pop(Path(out), None)
    if fd is not None:
        (Path(out) / LOCK).unlink(missing_ok=True)
        os.close(fd)
