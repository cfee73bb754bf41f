"""The cross-aligned style-transfer networks of thesis §3.3.2-3.3.4, as plain ``nn.Module``s.

* :class:`StyleCode` (E_y): style label -> style code y (eq. 3.8 auto-encoder, or a plain
  embedding for the ablation without it).
* :class:`SentenceEncoder` (E_z): a two-layer LSTM; the first layer starts from ``[y, 0]``,
  the second layer's last state is the content code z. Its LM head serves eq. 3.9.
* :class:`Generator` (G): a one-layer LSTM started from ``[z, y]``, word embedding shared
  with E_z; teacher forcing (eqs. 3.10-3.11) or free running with Gumbel-softmax inputs
  (eq. 3.12).
* :class:`TextCNN`: kernels over a masked sequence with max-over-time pooling; the N+1
  discriminator over G's hidden states (eq. 3.13) and, with its own embedding, the
  sentiment classifier of the evaluation (:mod:`dialogue.style.nets`).
"""

from __future__ import annotations

import torch
import torch.nn.functional as F  # noqa: N812
from torch import nn

from dialogue.style.config import ModelConfig
from textnets.copy import Memory
from textnets.generator import Generator, TiedOutput
from textnets.textcnn import TextCNN
from textnets.vocab import PAD_ID, UNK_ID

N_STYLES = 2
FAKE = N_STYLES  # the discriminator's extra class


class StyleCode(nn.Module):
    """E_y: a one-hot style label delta -> style code y in (-1, 1)^style_dim.

    With ``autoencoder`` (thesis Fig. 3.12) a decoder reconstructs delta from y and
    :meth:`loss` is eq. 3.8's mean squared error; without it y is a learned embedding.
    """

    def __init__(self, style_dim: int, hidden: int, autoencoder: bool = True) -> None:
        super().__init__()
        self.autoencoder = autoencoder
        if autoencoder:
            self.encode = nn.Sequential(nn.Linear(N_STYLES, hidden), nn.Tanh(),
                                        nn.Linear(hidden, style_dim), nn.Tanh())
            self.decode = nn.Sequential(nn.Linear(style_dim, hidden), nn.Tanh(),
                                        nn.Linear(hidden, N_STYLES))
        else:
            self.table = nn.Embedding(N_STYLES, style_dim)

    def forward(self, labels: torch.Tensor) -> torch.Tensor:
        """Style codes ``(B, style_dim)`` of integer labels ``(B,)``."""
        if not self.autoencoder:
            return torch.tanh(self.table(labels))
        return self.encode(F.one_hot(labels, N_STYLES).float())

    def loss(self, labels: torch.Tensor) -> torch.Tensor:
        """Eq. 3.8: MSE between delta and its reconstruction (zero without the auto-encoder)."""
        if not self.autoencoder:
            return torch.zeros(())
        delta = F.one_hot(labels, N_STYLES).float()
        return F.mse_loss(self.decode(self.encode(delta)), delta)


def last_state(states: torch.Tensor, lengths: torch.Tensor) -> torch.Tensor:
    """The states ``(B, T, C)`` at the last real positions ``lengths - 1`` -> ``(B, C)``."""
    last = (lengths - 1).clamp(min=0).to(states.device)
    return states[torch.arange(len(states)), last]


class SentenceEncoder(nn.Module):
    """E_z: embeddings ``(B, T, E)`` and style code -> second-layer states; the state after
    the last real word is the content code z (:meth:`StyleTransferModel.content`)."""

    def __init__(self, embed_dim: int, style_dim: int, content_dim: int, vocab: int) -> None:
        super().__init__()
        self.style_dim, self.content_dim = style_dim, content_dim
        self.layer1 = nn.LSTM(embed_dim, style_dim + content_dim, batch_first=True)
        self.layer2 = nn.LSTM(style_dim + content_dim, content_dim, batch_first=True)
        self.lm_head = TiedOutput(content_dim, embed_dim, vocab)

    def states(self, emb: torch.Tensor, y: torch.Tensor) -> torch.Tensor:
        """Second-layer outputs ``(B, T, content_dim)``; layer one starts from ``[y, 0]``."""
        h0 = torch.cat([y, y.new_zeros(len(y), self.content_dim)], 1)[None]
        out1, _ = self.layer1(emb, (h0, torch.zeros_like(h0)))
        out2, _ = self.layer2(out1)
        return out2

    def lm_logits(self, emb: torch.Tensor, y: torch.Tensor, table: torch.Tensor
                  ) -> torch.Tensor:
        """Next-word logits ``(B, T, V)`` for eq. 3.9's language-model pre-training."""
        return self.lm_head(self.states(emb, y), table)


class StyleTransferModel(nn.Module):
    """E_y, the shared word embedding, E_z, G and the N+1 discriminator D."""

    def __init__(self, vocab: int, cfg: ModelConfig) -> None:
        super().__init__()
        self.cfg = cfg
        self.style = StyleCode(cfg.style_dim, cfg.style_hidden, cfg.style_autoencoder)
        self.embedding = nn.Embedding(vocab, cfg.embed_dim, padding_idx=PAD_ID)
        self.encoder = SentenceEncoder(cfg.embed_dim, cfg.style_dim, cfg.content_dim, vocab)
        self.generator = Generator(cfg.embed_dim, cfg.style_dim, cfg.content_dim, vocab,
                                   cfg.attention)
        self.discriminator = TextCNN(self.generator.hidden, cfg.disc_filters,
                                     cfg.disc_kernels, N_STYLES + 1, cfg.disc_dropout)
        # style markers hidden from E_z (model.mask_ratio); filled by the training
        self.register_buffer("masked", torch.zeros(vocab, dtype=torch.bool))

    def set_masked(self, ids: list[int]) -> None:
        """Hide these word ids from E_z: its input shows ``<unk>`` in their place."""
        self.masked.zero_()
        self.masked[torch.as_tensor(ids, dtype=torch.long)] = True

    def mask_ids(self, inputs: torch.Tensor) -> torch.Tensor:
        """E_z's view of id inputs: masked words replaced by ``<unk>``."""
        return torch.where(self.masked[inputs], torch.full_like(inputs, UNK_ID), inputs)

    def mask_soft(self, words: torch.Tensor) -> torch.Tensor:
        """E_z's view of relaxed one-hot words ``(B, T, V)``: masked mass moves to ``<unk>``."""
        hidden = words * self.masked
        out = words - hidden
        out[..., UNK_ID] += hidden.sum(-1)
        return out

    def generator_parameters(self) -> list[nn.Parameter]:
        """Parameters of E_y, the embedding, E_z and G (everything but D)."""
        return [p for name, p in self.named_parameters() if not name.startswith("discrimin")]

    def content(self, enc_emb: torch.Tensor, lengths: torch.Tensor, y: torch.Tensor
                ) -> tuple[torch.Tensor, Memory | None]:
        """z = E_z(x, y) from E_z's input embeddings, and G's copy memory (None without
        ``model.attention``)."""
        states = self.encoder.states(enc_emb, y)
        z = last_state(states, lengths)
        if self.generator.copy is None:
            return z, None
        mask = torch.arange(states.shape[1])[None] < lengths[:, None]
        return z, Memory(states, enc_emb, mask)

    def encoder_inputs(self, inputs: torch.Tensor) -> torch.Tensor:
        """E_z's input embeddings of id inputs, masked words shown as ``<unk>``."""
        return self.embedding(self.mask_ids(inputs))

    def encode(self, inputs: torch.Tensor, lengths: torch.Tensor, labels: torch.Tensor
               ) -> tuple[torch.Tensor, Memory | None]:
        """z and the copy memory for id inputs ``<bos> w_1 .. w_n`` (masked words hidden)."""
        return self.content(self.encoder_inputs(inputs), lengths, self.style(labels))
