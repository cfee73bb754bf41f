"""Reading and writing the acoustic model's parameter files that adaptation needs.

pocketsphinx's wheel ships its en-US model's mixture weights only as a ``sendump``: 8-bit
quantised negative logarithms (base 1.0001, shifted left by 10 bits) of each codeword's
weight in each senone, stored codebook by codebook. SphinxTrain's tools read and write the
plain 32-bit float ``mixture_weights`` file instead. :func:`read_sendump` expands the
former and :func:`write_s3_array` writes the latter: a short text header (``s3``, key-value
lines, ``endhdr`` padded to a 4-byte boundary), a byte-order word, the array's dimensions,
its number of values and the values themselves.
"""

from __future__ import annotations

import struct
from pathlib import Path

import numpy as np

from core.errors import UserError

LOG_BASE = 1.0001        # the base of the quantised logarithms
SHIFT_BITS = 10          # each stored byte is the logarithm shifted right by this (default)
BYTE_ORDER = 0x11223344


class SphinxFileError(UserError):
    """A model file is not in the format expected."""


def read_sendump(path: Path) -> np.ndarray:
    """The mixture weights of ``path`` as a (senones, features, codewords) array, each
    senone's weights for a feature normalised to sum to one."""
    data = path.read_bytes()
    pos = 0

    def integer() -> int:
        nonlocal pos
        if pos + 4 > len(data):
            raise SphinxFileError(f"{path}: ends inside its header")
        (value,) = struct.unpack_from("<i", data, pos)
        pos += 4
        return value

    header: list[str] = []
    while (length := integer()) != 0:
        header.append(data[pos:pos + length].rstrip(b"\0").decode("ascii", "replace"))
        pos += length
    settings = dict(line.split(maxsplit=1) for line in header if line.count(" ") == 1)
    if settings.get("cluster_count", "0") != "0":
        raise SphinxFileError(f"{path}: clustered mixture weights are not supported")
    features = int(settings.get("feature_count", "1"))
    codewords, senones = integer(), integer()
    size = features * codewords * senones
    if pos + size > len(data):
        raise SphinxFileError(f"{path}: holds fewer weights than its header says")
    raw = np.frombuffer(data, dtype=np.uint8, count=size, offset=pos)
    shift = int(settings.get("mixw_shift", SHIFT_BITS))
    logs = raw.reshape(features, codewords, senones).astype(np.float64) * (1 << shift)
    weights = np.power(LOG_BASE, -logs).transpose(2, 0, 1)
    return weights / weights.sum(axis=2, keepdims=True)


def write_s3_array(path: Path, values: np.ndarray) -> None:
    """``values`` (any number of dimensions) as a SphinxTrain parameter file at ``path``."""
    head = b"s3\nversion 1.0\n"
    end = b"endhdr\n"
    pad = (-(len(head) + len(end))) % 4
    body = struct.pack("<I", BYTE_ORDER) + struct.pack(f"<{values.ndim}I", *values.shape)
    body += struct.pack("<I", values.size) + np.ascontiguousarray(values, "<f4").tobytes()
    path.write_bytes(head + b" " * pad + end + body)
