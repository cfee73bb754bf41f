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
from dialogue.style.training.data import PAD_ID, UNK_ID
from textnets.copy import CopyAttention, Memory

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


def masked_nll(logits: torch.Tensor, targets: torch.Tensor) -> torch.Tensor:
    """Summed token cross-entropy per sentence ``(B,)``; ``<pad>`` targets count zero."""
    nll = F.cross_entropy(logits.reshape(-1, logits.shape[-1]), targets.reshape(-1),
                          ignore_index=PAD_ID, reduction="none")
    return nll.view(targets.shape).sum(1)


def gumbel_softmax(logits: torch.Tensor, tau: float) -> torch.Tensor:
    """Eq. 3.12: ``softmax((p + G) / tau)`` with ``G = -log(-log(U))``, ``U ~ Unif(0, 1)``."""
    u = torch.rand_like(logits).clamp_(min=1e-10)
    return torch.softmax((logits - u.log_().neg_().log_()) / tau, -1)


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


class TextCNN(nn.Module):
    """Kim's TextCNN over a masked sequence of vectors ``(B, T, C)`` -> class logits."""

    def __init__(self, in_dim: int, filters: int, kernels: list[int], n_classes: int,
                 dropout: float) -> None:
        super().__init__()
        self.kernels = list(kernels)
        self.convs = nn.ModuleList(nn.Conv1d(in_dim, filters, k) for k in self.kernels)
        self.drop = nn.Dropout(dropout)
        self.fc = nn.Linear(filters * len(self.kernels), n_classes)

    def forward(self, x: torch.Tensor, mask: torch.Tensor) -> torch.Tensor:
        """Padded positions (``mask == 0``) neither feed nor win the max-over-time pooling."""
        t = x.shape[1]
        lengths = mask.sum(1).long()
        x = (x * mask[..., None]).transpose(1, 2)
        x = F.pad(x, (0, max(self.kernels) - 1))
        pooled = []
        for k, conv in zip(self.kernels, self.convs, strict=True):
            feat = F.relu(conv(x))[:, :, :t]
            valid = torch.arange(t, device=x.device)[None] <= (lengths - k).clamp(min=0)[:, None]
            pooled.append(feat.masked_fill(~valid[:, None], float("-inf")).amax(2))
        return self.fc(self.drop(torch.cat(pooled, 1)))


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
