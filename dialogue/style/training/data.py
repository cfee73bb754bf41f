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

import re
from collections import Counter
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import torch

from app.core.errors import UserError
from dialogue.style.config import DataConfig

PAD, BOS, EOS, UNK = "<pad>", "<bos>", "<eos>", "<unk>"
SPECIALS = (PAD, BOS, EOS, UNK)
PAD_ID, BOS_ID, EOS_ID, UNK_ID = range(4)
STYLES = ("negative", "positive")


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
    """Non-empty stripped lines of a UTF-8 file."""
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise StyleDataError(f"{path}: cannot read the Yelp data ({exc.strerror})") from None
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


class Vocab:
    """Word <-> id mapping; ids 0-3 are ``<pad> <bos> <eos> <unk>``."""

    def __init__(self, words: Sequence[str]) -> None:
        self.itos = list(words)
        if tuple(self.itos[:4]) != SPECIALS:
            raise ValueError("a vocabulary starts with <pad> <bos> <eos> <unk>")
        self.stoi = {w: i for i, w in enumerate(self.itos)}

    @classmethod
    def build(cls, sentences: Iterable[Sequence[str]], min_count: int) -> Vocab:
        """Words seen at least ``min_count`` times, most frequent first (ties alphabetical)."""
        counts = Counter(w for s in sentences for w in s)
        words = sorted((w for w, c in counts.items() if c >= min_count and w not in SPECIALS),
                       key=lambda w: (-counts[w], w))
        return cls([*SPECIALS, *words])

    def __len__(self) -> int:
        return len(self.itos)

    def encode(self, words: Sequence[str]) -> list[int]:
        """Ids of ``words``; unknown words become ``<unk>``."""
        return [self.stoi.get(w, UNK_ID) for w in words]

    def decode(self, ids: Iterable[int]) -> list[str]:
        """Words up to the first ``<eos>``, without ``<pad>`` and ``<bos>``."""
        out = []
        for i in ids:
            if i == EOS_ID:
                break
            if i not in (PAD_ID, BOS_ID):
                out.append(self.itos[i])
        return out


@dataclass
class Batch:
    """Padded sentences with their masks, as ``(B, T)`` tensors with ``T = max length + 1``.

    ``inputs`` is ``<bos> w_1 .. w_n`` and ``targets`` is ``w_1 .. w_n <eos>``; ``mask`` is
    1.0 on the ``n + 1`` real positions; ``lengths`` holds ``n + 1``.
    """

    inputs: torch.Tensor
    targets: torch.Tensor
    mask: torch.Tensor
    lengths: torch.Tensor
    labels: torch.Tensor


def make_batch(seqs: Sequence[Sequence[int]], labels: Sequence[int]) -> Batch:
    """Pad id sequences into a :class:`Batch`."""
    if len(seqs) == 0:
        raise ValueError("a batch needs at least one sentence")
    lengths = torch.tensor([len(s) + 1 for s in seqs])
    t = int(lengths.max())
    inputs = torch.full((len(seqs), t), PAD_ID, dtype=torch.long)
    targets = torch.full((len(seqs), t), PAD_ID, dtype=torch.long)
    for i, s in enumerate(seqs):
        ids = torch.as_tensor(list(s), dtype=torch.long)
        inputs[i, 0] = BOS_ID
        inputs[i, 1:len(s) + 1] = ids
        targets[i, :len(s)] = ids
        targets[i, len(s)] = EOS_ID
    mask = (torch.arange(t)[None] < lengths[:, None]).float()
    return Batch(inputs, targets, mask, lengths, torch.as_tensor(list(labels), dtype=torch.long))


class BatchSampler:
    """Endless, resumable batches of one list of id sequences, bucketed by length.

    Each epoch is a seeded permutation; chunks of ``bucket`` batches are sorted by length so
    that a batch holds sentences of similar length (less padding), and the batches of an
    epoch are shuffled. The state is ``(epoch, cursor)``: the permutation is re-derived.
    """

    def __init__(self, seqs: Sequence[Sequence[int]], label: int | Sequence[int],
                 batch_size: int, seed: int, bucket: int = 50) -> None:
        self.seqs = seqs
        self.labels = [label] * len(seqs) if isinstance(label, int) else list(label)
        self.batch_size = min(batch_size, len(seqs))
        self.seed, self.bucket = seed, bucket
        self.epoch, self.cursor = 0, 0
        self._order = self._epoch_batches()

    def _epoch_batches(self) -> list[np.ndarray]:
        rng = np.random.default_rng([self.seed, self.epoch])
        perm = rng.permutation(len(self.seqs))
        lengths = np.array([len(s) for s in self.seqs])
        batches = []
        size = self.batch_size * self.bucket
        for start in range(0, len(perm), size):
            chunk = perm[start:start + size]
            chunk = chunk[np.argsort(lengths[chunk], kind="stable")]
            batches += [chunk[i:i + self.batch_size]
                        for i in range(0, len(chunk), self.batch_size)]
        return [batches[i] for i in rng.permutation(len(batches))]

    def next(self) -> Batch:
        """The next batch (a new epoch starts when this one is used up)."""
        if self.cursor >= len(self._order):
            self.epoch, self.cursor = self.epoch + 1, 0
            self._order = self._epoch_batches()
        idx = self._order[self.cursor]
        self.cursor += 1
        return make_batch([self.seqs[i] for i in idx], [self.labels[i] for i in idx])

    def batches_per_epoch(self) -> int:
        """How many batches one pass over the data takes."""
        return len(self._order)

    def state_dict(self) -> dict[str, int]:
        """Position in the stream, for checkpoints."""
        return {"epoch": self.epoch, "cursor": self.cursor}

    def load_state_dict(self, state: dict[str, int]) -> None:
        """Continue from a saved position."""
        self.epoch, self.cursor = int(state["epoch"]), int(state["cursor"])
        self._order = self._epoch_batches()


def iterate_batches(seqs: Sequence[Sequence[int]], labels: Sequence[int],
                    batch_size: int) -> Iterable[Batch]:
    """Ordered, non-shuffled batches for evaluation."""
    for i in range(0, len(seqs), batch_size):
        yield make_batch(seqs[i:i + batch_size], labels[i:i + batch_size])


_PUNCT = re.compile(r"([.,!?;:()\"&])")
_CLITIC = re.compile(r"(\w)(n't|'s|'re|'ve|'m|'ll|'d)\b")
_NUMBER = re.compile(r"^\d+([.,:]\d+)*$")


def tokenize(text: str) -> list[str]:
    """Lower-case and split free text the way the Yelp files are: ``didn't`` -> ``did n't``."""
    text = text.lower().replace("\u2019", "'")
    text = _CLITIC.sub(r"\1 \2", text)
    text = _PUNCT.sub(r" \1 ", text)
    return ["_num_" if _NUMBER.match(w) else w for w in text.split()]


def detokenize(words: Sequence[str]) -> str:
    """A readable sentence from tokens: ``it 's good !`` -> ``it's good!``."""
    text = " ".join(words)
    text = re.sub(r" (n't|'s|'re|'ve|'m|'ll|'d)\b", r"\1", text)
    return re.sub(r" ([.,!?;:)])", r"\1", text).replace("( ", "(")
