"""Padded batches of id sequences for the sequence models (style transfer, VQG): teacher-forcing
inputs and targets with their masks, endless resumable sampling bucketed by length, and
ordered batches for evaluation."""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np
import torch

from textnets.vocab import BOS_ID, EOS_ID, PAD_ID


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
