"""A copy path for the generator G: attention over the (marker-masked) source words.

The thesis's G sees the source sentence only through the content code z, and with a
CPU-sized z it reconstructs sentences poorly (about 1 nat a word after two epochs), which
caps how much content a transfer keeps. With ``model.attention`` each step of G also
attends over the source positions: the keys are E_z's second-layer states, the values
the embeddings of the words E_z saw, so with ``model.mask_ratio`` style markers are
``<unk>`` there and cannot be copied. The attended embedding enters the tied output in
embedding space, which raises the logits of the attended words (a soft copy, in the spirit
of Luong et al. 2015 and of the delete-and-generate model of Li et al. 2018).
"""

from __future__ import annotations

from dataclasses import dataclass

import torch
from torch import nn


@dataclass
class Memory:
    """What G may attend to: keys ``(B, S, K)``, values ``(B, S, E)``, mask ``(B, S)``."""

    keys: torch.Tensor
    values: torch.Tensor
    mask: torch.Tensor

    def select(self, rows: torch.Tensor) -> Memory:
        """The memories of these batch rows (e.g. one per beam)."""
        return Memory(self.keys[rows], self.values[rows], self.mask[rows])


def select(memory: Memory | None, rows: torch.Tensor) -> Memory | None:
    """:meth:`Memory.select`, passing None (a model without the copy path) through."""
    return None if memory is None else memory.select(rows)


class CopyAttention(nn.Module):
    """Bilinear attention of G's states over a :class:`Memory`, returned in embedding space."""

    def __init__(self, hidden: int, key_dim: int, embed_dim: int) -> None:
        super().__init__()
        self.query = nn.Linear(hidden, key_dim, bias=False)
        self.mix = nn.Linear(embed_dim, embed_dim)

    def forward(self, h: torch.Tensor, memory: Memory) -> torch.Tensor:
        """Attended values ``(B, [T,] E)`` for states ``(B, [T,] H)``."""
        single = h.dim() == 2
        q = self.query(h[:, None] if single else h)
        scores = q @ memory.keys.transpose(1, 2)
        scores = scores.masked_fill(~memory.mask[:, None], float("-inf"))
        context = self.mix(torch.softmax(scores, -1) @ memory.values)
        return context[:, 0] if single else context
