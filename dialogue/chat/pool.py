"""The retrieval pool: references to the training pairs of a chit-chat model, shipped beside
its model file; the pairs' text is read in place from the data when the model loads.

The robot cannot rebuild the training split at run time (the data readers and the split are
training tooling), and the shared data must not be copied into the project. So training
writes ``<model>.pool.jsonl`` next to ``<model>.pt``: a header line (format, the data config,
the number of pairs) and then, per training pair in split order, where its text lies and a
check of it: ``[source, file, first, second, hash]`` (:mod:`dialogue.chat.sources` explains
the position; ``hash`` is the first 16 hex digits of the SHA-256 of the normalised pair).
Only the training split is written, so no held-out pair can ever be retrieved.

Loading reads the referenced lines, normalises them as training did and keeps a pair only
when its hash still matches: a pair whose data is missing (no Papaya folder, no
chatterbot-corpus package, a shorter file) or changed is left out, and counted.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from core.checkpoint import atomic_write_bytes
from core.errors import UserError
from dialogue.chat.sources import Ref, SourceTexts
from dialogue.chat.text import Pair, pair_tokens

POOL_FORMAT = "companion-chat-pool-2"
SOURCES = ("papaya", "chatterbot")


class ChatPoolError(UserError):
    """A retrieval pool file is unreadable or belongs to other data than its model."""


@dataclass
class Pool:
    """The training pairs of a pool whose data was found unchanged, and how many were not."""

    pairs: list[Pair]
    left_out: int
    total: int


def pool_path(model_path: str | Path) -> Path:
    """Where the pool of the model file ``model_path`` lies (``chat.pt`` -> ``chat.pool.jsonl``)."""
    return Path(model_path).with_suffix(".pool.jsonl")


def pair_hash(pair: Pair) -> str:
    """A short check of a normalised pair: a changed data line no longer matches it."""
    text = " ".join(pair[0]) + "\t" + " ".join(pair[1])
    return hashlib.sha256(text.encode("utf-8")).hexdigest()[:16]


def write_pool(path: str | Path, pairs: Sequence[Pair], refs: Sequence[Ref],
               data_config: dict[str, Any]) -> None:
    """Write the references of ``pairs`` (the training split; ``refs[i]`` is where pair
    ``i`` came from) with a header naming the data config they came from."""
    if len(pairs) != len(refs):
        raise ValueError(f"{len(pairs)} pairs but {len(refs)} references")
    lines = [json.dumps({"format": POOL_FORMAT, "data": data_config, "pairs": len(pairs)},
                        sort_keys=True)]
    lines += [json.dumps([*ref, pair_hash(pair)], ensure_ascii=False)
              for pair, ref in zip(pairs, refs, strict=True)]
    atomic_write_bytes(path, ("\n".join(lines) + "\n").encode("utf-8"))


def read_pool(path: str | Path, data_config: dict[str, Any],
              papaya_dir: Path | None) -> Pool:
    """The pairs of a pool file, checked against the model's ``data_config`` and read from
    the Papaya folder ``papaya_dir`` and the chatterbot-corpus package."""
    try:
        header, *rows = Path(path).read_text(encoding="utf-8").splitlines()
        head = json.loads(header)
        entries = [_entry(json.loads(row)) for row in rows]
    except (OSError, ValueError, TypeError) as exc:
        raise ChatPoolError(f"{path}: not a readable retrieval pool ({exc})") from None
    rebuild = "rebuild it with `companion train chat-pool --model MODEL`"
    if not isinstance(head, dict) or head.get("format") != POOL_FORMAT:
        raise ChatPoolError(f"{path}: not a retrieval pool (format {POOL_FORMAT}); {rebuild}")
    if head.get("data") != data_config or head.get("pairs") != len(entries):
        raise ChatPoolError(f"{path}: built from other data than its model; {rebuild}")
    texts = SourceTexts(papaya_dir)
    pairs = []
    for ref, digest in entries:
        text = texts.text(ref)
        pair = pair_tokens(*text) if text is not None else None
        if pair is not None and pair_hash(pair) == digest:
            pairs.append(pair)
    return Pool(pairs, len(entries) - len(pairs), len(entries))


def _entry(row: Any) -> tuple[Ref, str]:
    """One row's reference and hash; ValueError for anything else."""
    if not isinstance(row, list) or len(row) != 5:
        raise ValueError("a row is not [source, file, first, second, hash]")
    source, name, first, second, digest = row
    if source not in SOURCES or not isinstance(name, str) or not isinstance(digest, str) \
            or not all(isinstance(i, int) and not isinstance(i, bool) for i in (first, second)):
        raise ValueError(f"a malformed reference {row}")
    return (source, name, first, second), digest
