"""The retrieval pool: the training pairs of a chit-chat model, shipped beside its model file.

The robot cannot rebuild the training split at run time (the data readers are training
tooling), so training writes the split's pairs to ``<model>.pool.jsonl`` next to
``<model>.pt``: a header line (format, the data config, the number of pairs) and then one
``[input tokens, reply tokens]`` line per pair, in split order. Only the training split is
written, so no held-out pair can ever be retrieved.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from app.core.checkpoint import atomic_write_bytes
from app.core.errors import UserError
from dialogue.chat.text import Pair

POOL_FORMAT = "companion-chat-pool-1"


class ChatPoolError(UserError):
    """A retrieval pool file is unreadable or belongs to other data than its model."""


def pool_path(model_path: str | Path) -> Path:
    """Where the pool of the model file ``model_path`` lies (``chat.pt`` -> ``chat.pool.jsonl``)."""
    return Path(model_path).with_suffix(".pool.jsonl")


def write_pool(path: str | Path, pairs: Sequence[Pair], data_config: dict[str, Any]) -> None:
    """Write ``pairs`` (the training split) with a header naming the data they came from."""
    lines = [json.dumps({"format": POOL_FORMAT, "data": data_config, "pairs": len(pairs)},
                        sort_keys=True)]
    lines += [json.dumps([list(src), list(tgt)], ensure_ascii=False) for src, tgt in pairs]
    atomic_write_bytes(path, ("\n".join(lines) + "\n").encode("utf-8"))


def read_pool(path: str | Path, data_config: dict[str, Any]) -> list[Pair]:
    """The pairs of a pool file, checked against the model's ``data_config``."""
    try:
        header, *rows = Path(path).read_text(encoding="utf-8").splitlines()
        head = json.loads(header)
        pairs = [(tuple(src), tuple(tgt)) for src, tgt in map(json.loads, rows)]
    except (OSError, ValueError, TypeError) as exc:
        raise ChatPoolError(f"{path}: not a readable retrieval pool ({exc})") from None
    if not isinstance(head, dict) or head.get("format") != POOL_FORMAT:
        raise ChatPoolError(f"{path}: not a retrieval pool (format {POOL_FORMAT})")
    if head.get("data") != data_config or head.get("pairs") != len(pairs):
        raise ChatPoolError(f"{path}: built from other data than its model; rebuild it with "
                            "`companion train chat-pool --model MODEL`")
    return pairs
