"""Reading the user's files through one door: every OS error (not found, a directory, no
permission, a FIFO or device that would block) and every decode error becomes a
:class:`~core.errors.UserError` naming the file, and files larger than a limit are
refused before they are read (a 50 MB scenario must not take a gigabyte of memory)."""

from __future__ import annotations

import errno
import os
import stat
from pathlib import Path

from core.errors import UserError

TEXT_LIMIT = 1 << 20   # bytes: scenarios, configs, personalities and text inputs
DATA_LIMIT = 1 << 30   # bytes: a data set's own files (question lists, logs)


class FileReadError(UserError, OSError):
    """A user file cannot be read; the message names the file and why."""


def _why(exc: OSError) -> str:
    reasons = {errno.ENOENT: "file not found", errno.EISDIR: "is a directory, not a file",
               errno.EACCES: "permission denied", errno.ENOTDIR: "a parent is not a folder",
               errno.ELOOP: "too many symbolic links", errno.ENAMETOOLONG: "name too long"}
    return reasons.get(exc.errno or 0, exc.strerror or type(exc).__name__)


def read_bytes(path: str | Path, limit: int = TEXT_LIMIT) -> bytes:
    """The bytes of the regular file ``path``, at most ``limit`` of them.

    The file is opened without blocking and checked to be a regular file before anything
    is read, so a FIFO or a device given by mistake is refused instead of hanging.
    """
    path = Path(path)
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK)
    except OSError as exc:
        raise FileReadError(f"{path}: {_why(exc)}") from None
    try:
        info = os.fstat(fd)
        if stat.S_ISDIR(info.st_mode):
            raise FileReadError(f"{path}: is a directory, not a file")
        if not stat.S_ISREG(info.st_mode):
            raise FileReadError(f"{path}: not a regular file (a pipe, socket or device)")
        if info.st_size > limit:
            raise FileReadError(f"{path}: {info.st_size:,} bytes is larger than the "
                                f"{limit:,}-byte limit of this kind of file")
        with os.fdopen(fd, "rb", closefd=False) as fh:
            data = fh.read(limit + 1)
    except OSError as exc:
        if isinstance(exc, FileReadError):
            raise
        raise FileReadError(f"{path}: {_why(exc)}") from None
    finally:
        os.close(fd)
    if len(data) > limit:
        raise FileReadError(f"{path}: larger than the {limit:,}-byte limit of this kind of file")
    return data


def read_text(path: str | Path, limit: int = TEXT_LIMIT) -> str:
    """The UTF-8 text of ``path`` (see :func:`read_bytes`); a UTF-8 byte-order mark is
    dropped, and a file in another encoding or a binary one is refused by name."""
    data = read_bytes(path, limit)
    if b"\x00" in data:
        raise FileReadError(f"{path}: a binary file (or UTF-16 text), expected UTF-8 text")
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise FileReadError(f"{path}: not UTF-8 text (byte {exc.start}: "
                            f"{data[exc.start:exc.start + 1]!r})") from None
