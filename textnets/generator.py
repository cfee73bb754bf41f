"""The LSTM sentence generator G of the cross-aligned auto-encoder (thesis §3.3.3), shared by
style transfer (started from a content and a style code) and VQG (started from an image and
a latent code): teacher forcing, or free running on Gumbel-softmax words (eq. 3.12), with
the output tied to the word embedding and an optional copy attention over source words."""

from __future__ import annotations

import torch
import torch.nn.functional as F  # noqa: N812
from torch import nn

from textnets.copy import CopyAttention, Memory
from textnets.functional import gumbel_softmax


class TiedOutput(nn.Module):
    """Next-word logits through the shared word embedding: ``W_e (A h) + b``.

    Projecting the state to the embedding size first and scoring words against the
    embedding table (Press & Wolf, 2017) cuts the vocabulary projection, the dominant cost
    on a CPU, by ``hidden / embed_dim``.
    """

    def __init__(self, hidden: int, embed_dim: int, vocab: int) -> None:
        super().__init__()
        self.proj = nn.Linear(hidden, embed_dim)
        self.bias = nn.Parameter(torch.zeros(vocab))

    def forward(self, h: torch.Tensor, table: torch.Tensor,
                extra: torch.Tensor | None = None) -> torch.Tensor:
        """Logits ``(..., V)`` of states ``(..., hidden)`` against the table ``(V, E)``;
        ``extra`` (embedding space, e.g. a copied word) is added before scoring."""
        e = self.proj(h)
        return F.linear(e if extra is None else e + extra, table, self.bias)


class Generator(nn.Module):
    """G: a one-layer LSTM whose initial hidden state is ``[z, y]``; with ``attention`` its
    output also attends over the source words (:mod:`textnets.copy`)."""

    def __init__(self, embed_dim: int, style_dim: int, content_dim: int, vocab: int,
                 attention: bool = False) -> None:
        super().__init__()
        self.hidden = style_dim + content_dim
        self.lstm = nn.LSTM(embed_dim, self.hidden, batch_first=True)
        self.out = TiedOutput(self.hidden, embed_dim, vocab)
        self.copy = CopyAttention(self.hidden, content_dim, embed_dim) if attention else None

    def logits(self, h: torch.Tensor, table: torch.Tensor, memory: Memory | None = None
               ) -> torch.Tensor:
        """Next-word logits of states ``(B, [T,] H)``, copying from ``memory`` if given."""
        extra = self.copy(h, memory) if self.copy is not None and memory is not None else None
        return self.out(h, table, extra)

    @staticmethod
    def initial(z: torch.Tensor, y: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        """``(h0, c0)``: h0 = [z, y], c0 = 0."""
        h0 = torch.cat([z, y], 1)
        return h0, torch.zeros_like(h0)

    def teacher_force(self, emb: torch.Tensor, z: torch.Tensor, y: torch.Tensor,
                      table: torch.Tensor, memory: Memory | None = None
                      ) -> tuple[torch.Tensor, torch.Tensor]:
        """Hidden states ``(B, T, H)`` and logits ``(B, T, V)`` given the true inputs."""
        h0, c0 = self.initial(z, y)
        hidden, _ = self.lstm(emb, (h0[None], c0[None]))
        return hidden, self.logits(hidden, table, memory)

    def step(self, x: torch.Tensor, state: tuple[torch.Tensor, torch.Tensor]
             ) -> tuple[torch.Tensor, torch.Tensor]:
        """One LSTM step with the module's own weights (inputs ``(B, E)``)."""
        h, c = state
        lstm = self.lstm
        gates = (x @ lstm.weight_ih_l0.T + lstm.bias_ih_l0
                 + h @ lstm.weight_hh_l0.T + lstm.bias_hh_l0)
        i, f, g, o = gates.chunk(4, 1)
        c = torch.sigmoid(f) * c + torch.sigmoid(i) * torch.tanh(g)
        return torch.sigmoid(o) * torch.tanh(c), c

    def free_run(self, embedding: nn.Embedding, start: torch.Tensor, z: torch.Tensor,
                 y: torch.Tensor, steps: int, tau: float, memory: Memory | None = None
                 ) -> tuple[torch.Tensor, torch.Tensor]:
        """Eq. 3.12: unroll ``steps`` steps feeding back ``softmax((logits + g) / tau)``.

        ``start`` is the ``<bos>`` embedding ``(E,)``. Returns the hidden states
        ``(B, steps, H)`` and the relaxed one-hot words ``(B, steps, V)``.
        """
        state = self.initial(z, y)
        x = start.expand(len(z), -1)
        hidden, words = [], []
        for _ in range(steps):
            state = self.step(x, state)
            w = gumbel_softmax(self.logits(state[0], embedding.weight, memory), tau)
            x = w @ embedding.weight
            hidden.append(state[0])
            words.append(w)
        return torch.stack(hidden, 1), torch.stack(words, 1)
