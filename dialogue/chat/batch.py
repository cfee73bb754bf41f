"""Padded batches of (utterance, reply) pairs for the seq2seq chit-chat model."""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass

import numpy as np
import torch

from dialogue.chat.text import Pair
from textnets.vocab import BOS_ID, EOS_ID, PAD_ID, UNK_ID, Vocab


@dataclass(frozen=True)
class Batch:
    """Padded tensors of one batch; masks are True on real tokens."""

    src: torch.Tensor  # (B, S) utterance ids
    src_mask: torch.Tensor  # (B, S)
    tgt_in: torch.Tensor  # (B, T) <bos> + reply
    tgt_out: torch.Tensor  # (B, T) reply + <eos>
    tgt_mask: torch.Tensor  # (B, T)


def _pad(rows: Sequence[Sequence[int]]) -> torch.Tensor:
    out = torch.full((len(rows), max(len(r) for r in rows)), PAD_ID, dtype=torch.long)
    for i, r in enumerate(rows):
        out[i, : len(r)] = torch.tensor(r, dtype=torch.long)
    return out


def make_batch(pairs: Sequence[Pair], vocab: Vocab) -> Batch:
    """One padded batch of ``pairs`` (empty utterances get a single ``<unk>``)."""
    src = _pad([vocab.encode(s) or [UNK_ID] for s, _ in pairs])
    tgt = [vocab.encode(t) for _, t in pairs]
    tgt_in, tgt_out = _pad([[BOS_ID, *t] for t in tgt]), _pad([[*t, EOS_ID] for t in tgt])
    return Batch(src, src != PAD_ID, tgt_in, tgt_out, tgt_out != PAD_ID)


def batches(pairs: Sequence[Pair], vocab: Vocab, batch_size: int,
            rng: np.random.Generator | None = None) -> Iterator[Batch]:
    """Batches over ``pairs``, shuffled when ``rng`` is given (the last one may be short)."""
    order = rng.permutation(len(pairs)) if rng is not None else np.arange(len(pairs))
    for start in range(0, len(order), batch_size):
        yield make_batch([pairs[i] for i in order[start:start + batch_size]], vocab)
