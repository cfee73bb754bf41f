"""Chit-chat data: Papaya plus the English chatterbot corpus as (utterance -> reply) pairs.

* **Papaya** (``data.papaya_dir``): ``Q:``/``A:`` lines, conversations separated by ``===``.
  Each ``Q`` with the ``A`` after it is a pair (the robot's side is always ``A``).
  ``_func_val_...`` tokens (client functions) are removed; slots such as ``_unk_`` or
  ``_name_`` become ``<unk>`` in an utterance, and a reply that needs a slot is dropped.
* **chatterbot-corpus** (the PyPI package, ``data/english/*.yml`` less
  ``data.chatterbot_exclude``): every two consecutive lines of a conversation are a pair.

Text is lower-cased and tokenised PTB-style (``do n't``, ``i 'm``, punctuation apart), the
form Papaya already has. Pairs without a letter or digit on either side, or longer than
``data.max_len`` tokens on either side, are dropped; so are repeated pairs and, beyond the
first ``data.max_replies_per_input``, further replies to the same normalised utterance.
Whole conversations are then dealt to test, validation and training (seeded); a held-out
pair whose utterance also occurs in an earlier split is dropped, so no utterance leaks.
Files are read through :mod:`dialogue.chat.sources`, and every pair keeps where it lies
there, for the retrieval pool.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass, field
from itertools import pairwise
from pathlib import Path

import numpy as np

from core.errors import UserError
from dialogue.chat import sources
from dialogue.chat.config import ChatDataConfig
from dialogue.chat.sources import Ref, chatterbot_conversations, papaya_lines, papaya_pair
from dialogue.chat.text import Pair, pair_tokens
from textnets.vocab import UNK

SPLITS = ("train", "valid", "test")


class ChatDataError(UserError):
    """The chit-chat data is missing or unreadable."""


@dataclass
class Conversation:
    """The (utterance, reply) pairs of one conversation, still as raw text, and where each
    pair lies (``refs``, parallel to ``pairs``; see :mod:`dialogue.chat.sources`)."""

    source: str
    pairs: list[tuple[str, str]] = field(default_factory=list)
    refs: list[Ref] = field(default_factory=list)


@dataclass
class ChatData:
    """Tokenised pairs per split, where each came from (``refs``, parallel to ``splits``)
    and the counts of every filtering step."""

    splits: dict[str, list[Pair]]
    counts: dict[str, dict[str, int]]
    refs: dict[str, list[Ref]]


def read_papaya(folder: Path) -> list[Conversation]:
    """Conversations of every ``*.txt`` file in ``folder``, ``_func_val_`` tokens removed."""
    files = sorted(folder.glob("*.txt")) if folder.is_dir() else []
    if not files:
        raise ChatDataError(f"{folder}: no Papaya *.txt files (set data.papaya_dir, or null "
                            "to train without them)")
    convs: list[Conversation] = []
    for path in files:
        lines = papaya_lines(path)
        conv, question = Conversation(f"papaya/{path.stem}"), None
        for i, line in enumerate([*lines, "==="]):
            line = line.strip()
            if line.startswith("==="):
                if conv.pairs:
                    convs.append(conv)
                conv, question = Conversation(f"papaya/{path.stem}"), None
            elif line.startswith("Q:"):
                question = i
            elif line.startswith("A:") and question is not None:
                conv.pairs.append(papaya_pair(lines[question], line))
                conv.refs.append(("papaya", path.name, question, i))
                question = None
    return convs


def chatterbot_dir() -> Path:
    """The English folder of the installed ``chatterbot-corpus`` package."""
    folder = sources.chatterbot_dir()
    if folder is None:
        raise ChatDataError("the chatterbot-corpus package is not installed (pip install "
                            "chatterbot-corpus), or set data.chatterbot: false")
    return folder


def read_chatterbot(exclude: Sequence[str] = ()) -> list[Conversation]:
    """Consecutive-line pairs of the English chatterbot conversations."""
    convs = []
    for path in sorted(chatterbot_dir().glob("*.yml")):
        if path.stem in exclude:
            continue
        for c, lines in enumerate(chatterbot_conversations(path)):
            conv = Conversation(f"chatterbot/{path.stem}", list(pairwise(lines)),
                                [("chatterbot", path.name, c, i) for i in range(len(lines) - 1)])
            if conv.pairs:
                convs.append(conv)
    return convs


def _has_word(tokens: Sequence[str]) -> bool:
    return any(t != UNK and t[:1].isalnum() for t in tokens)


def _source_of(name: str) -> str:
    return name.split("/", 1)[0]


def load_chat_data(cfg: ChatDataConfig) -> ChatData:
    """Read, normalise, filter, deduplicate and split the configured conversations."""
    convs = read_papaya(p) if (p := cfg.resolved_papaya()) is not None else []
    if cfg.chatterbot:
        convs += read_chatterbot(cfg.chatterbot_exclude)
    if not convs:
        raise ChatDataError("no chit-chat data: enable data.papaya_dir or data.chatterbot")
    counts: dict[str, Counter] = {}
    seen_pairs: set[Pair] = set()
    replies_per_input: Counter = Counter()
    kept: list[tuple[int, Pair, Ref]] = []
    for i, conv in enumerate(convs):
        c = counts.setdefault(_source_of(conv.source), Counter())
        c["conversations"] += 1
        for (q, a), ref in zip(conv.pairs, conv.refs, strict=True):
            c["raw_pairs"] += 1
            src, tgt = pair_tokens(q, a)
            if UNK in tgt or not _has_word(src) or not _has_word(tgt):
                c["dropped_empty_or_slot"] += 1
            elif len(src) > cfg.max_len or len(tgt) > cfg.max_len:
                c["dropped_too_long"] += 1
            elif (src, tgt) in seen_pairs:
                c["dropped_duplicate_pair"] += 1
            elif replies_per_input[src] >= cfg.max_replies_per_input:
                c["dropped_duplicate_input"] += 1
            else:
                seen_pairs.add((src, tgt))
                replies_per_input[src] += 1
                kept.append((i, (src, tgt), ref))
                c["kept"] += 1
    dealt = _split(kept, len(convs), cfg, counts)
    if cfg.max_pairs is not None:
        dealt = {k: v[: max(1, round(cfg.max_pairs * f))]
                 for (k, v), f in zip(dealt.items(), cfg.split, strict=True)}
    splits = {k: [pair for pair, _ in v] for k, v in dealt.items()}
    total = {k: sum(c.get(k, 0) for c in counts.values())
             for k in sorted({k for c in counts.values() for k in c})}
    out = {name: dict(c) for name, c in counts.items()} | {"total": total}
    out["split"] = {k: len(v) for k, v in splits.items()}
    return ChatData(splits, out, {k: [ref for _, ref in v] for k, v in dealt.items()})


def _split(kept: list[tuple[int, Pair, Ref]], n_convs: int, cfg: ChatDataConfig,
           counts: dict[str, Counter]) -> dict[str, list[tuple[Pair, Ref]]]:
    """Deal whole conversations to test, then validation, then training (seeded)."""
    order = np.random.default_rng(cfg.seed).permutation(n_convs)
    per_conv: dict[int, list[tuple[Pair, Ref]]] = {}
    for i, pair, ref in kept:
        per_conv.setdefault(i, []).append((pair, ref))
    quota = {"test": cfg.split[2] * len(kept), "valid": cfg.split[1] * len(kept)}
    splits: dict[str, list[tuple[Pair, Ref]]] = {k: [] for k in SPLITS}
    for i in order:
        name = next((k for k in ("test", "valid") if len(splits[k]) < quota[k]), "train")
        splits[name].extend(per_conv.get(int(i), []))
    seen = {pair[0] for pair, _ in splits["train"]}
    leaks = Counter()
    for name in ("valid", "test"):
        clean = [item for item in splits[name] if item[0][0] not in seen]
        leaks[f"dropped_leak_{name}"] = len(splits[name]) - len(clean)
        splits[name] = clean
        seen |= {pair[0] for pair, _ in clean}
    counts["split_leaks"] = leaks
    return {k: splits[k] for k in SPLITS}


