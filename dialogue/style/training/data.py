"""The Yelp sentiment data: a seeded re-split, the vocabulary, tokenisation and batches.

Only Shen et al.'s dev and test files are available, so both are pooled per class and
re-split: exact duplicate lines are dropped within a class (so no sentence sits in both the
training and the test split), sentences longer than ``max_words`` are dropped, the rest is
shuffled with ``data.seed`` and cut 80/10/10 (``data.split``) per class. Class 0 is
negative, class 1 positive. The files are already lower-cased and tokenised (PTB style:
``did n't``, ``it 's``, numbers as ``_num_``); :func:`tokenize` brings free text into the
same form.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from core.errors import UserError
from core.files import FileReadError, read_text
from dialogue.style.config import DataConfig
from textnets.vocab import Vocab

FILE_LIMIT = 256 << 20   # bytes: the largest Yelp file is 3 MB


class StyleDataError(UserError):
    """The Yelp files are missing or unreadable."""


@dataclass(frozen=True)
class Split:
    """Tokenised sentences of one split with their labels (0 negative, 1 positive)."""

    sentences: list[list[str]]
    labels: list[int]

    def of_class(self, label: int) -> list[list[str]]:
        """The sentences carrying ``label``."""
        return [s for s, y in zip(self.sentences, self.labels, strict=True) if y == label]


def read_lines(path: Path) -> list[str]:
    """Non-empty stripped lines of a UTF-8 file of at most :data:`FILE_LIMIT` bytes; one that
    cannot be read raises :class:`StyleDataError` naming it."""
    try:
        text = read_text(path, FILE_LIMIT)
    except FileReadError as exc:
        raise StyleDataError(f"{exc} (a file of the Yelp data)") from None
    return [line.strip() for line in text.splitlines() if line.strip()]


def load_splits(cfg: DataConfig) -> dict[str, Split]:
    """Pool the configured files per class and re-split them (see the module docstring)."""
    root = cfg.resolved_dir()
    rng = np.random.default_rng(cfg.seed)
    parts: dict[str, tuple[list[list[str]], list[int]]] = {
        k: ([], []) for k in ("train", "valid", "test")}
    for label, names in enumerate((cfg.negative, cfg.positive)):
        lines = [line for name in names for line in read_lines(root / name)]
        if cfg.dedupe:
            lines = list(dict.fromkeys(lines))
        sents = [s for s in (line.split() for line in lines) if len(s) <= cfg.max_words]
        order = rng.permutation(len(sents))
        if cfg.max_per_class is not None:
            order = order[: cfg.max_per_class]
        n_train = round(cfg.split[0] * len(order))
        n_valid = round(cfg.split[1] * len(order))
        cuts = {"train": order[:n_train], "valid": order[n_train:n_train + n_valid],
                "test": order[n_train + n_valid:]}
        for key, idx in cuts.items():
            parts[key][0].extend(sents[i] for i in idx)
            parts[key][1].extend([label] * len(idx))
    return {k: Split(s, y) for k, (s, y) in parts.items()}


def style_markers(train: Split, vocab: Vocab, ratio: float, min_count: int) -> list[str]:
    """Words whose frequency differs between the styles by at least ``ratio``.

    With add-one smoothing, ``w`` is a marker when ``p(w | one style) / p(w | other)`` is
    ``ratio`` or more and it occurs ``min_count`` times. The content check ignores them.
    """
    counts = [Counter(w for s in train.of_class(c) for w in s) for c in (0, 1)]
    totals = [sum(c.values()) or 1 for c in counts]
    markers = []
    for w in vocab.itos[4:]:
        n0, n1 = counts[0][w], counts[1][w]
        if n0 + n1 < min_count:
            continue
        p0, p1 = (n0 + 1) / totals[0], (n1 + 1) / totals[1]
        if max(p0 / p1, p1 / p0) >= ratio:
            markers.append(w)
    return markers
