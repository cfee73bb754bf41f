"""The visual question generator of thesis §3.4 (Figs. 3.16-3.20) as plain ``nn.Module``s.

* :class:`ImageEncoder` (E_I): a small VGG-style CNN trained from scratch on the renders
  (the thesis uses a frozen ImageNet VGG16), pooled to a coarse grid and projected to the
  image feature ``f = tanh(W x)`` (512-d). A bag-of-words head on f pre-trains it.
* :class:`QuestionEncoder` (E_z): an LSTM whose initial state is f; its state after the
  last word goes through :class:`Latent`: a categorical VAE with Gumbel-softmax (eq. 3.15,
  16 variables x 8 classes) or, for the ablation, a Gaussian one.
* G: :class:`dialogue.style.model.Generator`, one LSTM started from ``[z, f]`` (640 units),
  word embedding shared with E_z and D2; teacher forcing or Gumbel-relaxed free running.
* D1: :class:`dialogue.style.model.TextCNN` (kernels 1-4) over G's hidden-state sequences
  (professor forcing, eq. 3.17).
* :class:`MatchDiscriminator` (D2, Fig. 3.20): conv (kernel 2) + LSTM over the words, last
  state dotted with f (eq. 3.18).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import torch
import torch.nn.functional as F  # noqa: N812
from torch import nn

from perception.vqg.config import ModelConfig
from textnets.batch import Batch
from textnets.functional import gumbel_softmax, masked_nll
from textnets.generator import Generator
from textnets.textcnn import TextCNN
from textnets.vocab import BOS_ID, EOS_ID, PAD_ID, UNK_ID


class ImageEncoder(nn.Module):
    """E_I: uint8 images ``(B, 3, H, W)`` -> trunk features -> f ``(B, feature_dim)``."""

    def __init__(self, cfg: ModelConfig) -> None:
        super().__init__()
        layers: list[nn.Module] = []
        c_in = 3
        for block in cfg.blocks:
            for c in block:
                layers += [nn.Conv2d(c_in, c, 3, padding=1), nn.BatchNorm2d(c), nn.ReLU()]
                c_in = c
            layers.append(nn.MaxPool2d(2))
        self.trunk = nn.Sequential(*layers, nn.AdaptiveAvgPool2d(cfg.pool_grid), nn.Flatten())
        self.trunk_dim = c_in * cfg.pool_grid[0] * cfg.pool_grid[1]
        self.drop = nn.Dropout(cfg.image_dropout)
        self.proj = nn.Linear(self.trunk_dim, cfg.feature_dim)

    def features(self, images: torch.Tensor) -> torch.Tensor:
        """Trunk features ``(B, trunk_dim)`` of uint8 images (frozen after pre-training)."""
        return self.trunk(images.float() / 127.5 - 1.0)

    def forward(self, feats: torch.Tensor) -> torch.Tensor:
        """The image feature f in (-1, 1) from trunk features."""
        return torch.tanh(self.proj(self.drop(feats)))


class Latent(nn.Module):
    """E_z's last state -> latent code z, with its KL divergence to the prior."""

    def __init__(self, hidden: int, cfg: ModelConfig) -> None:
        super().__init__()
        self.kind, self.vars, self.classes = cfg.latent, cfg.latent_vars, cfg.latent_classes
        self.dim = cfg.latent_dim
        self.head = nn.Linear(hidden, self.dim * (1 if self.kind == "gumbel" else 2))

    def forward(self, h: torch.Tensor, tau: float) -> tuple[torch.Tensor, torch.Tensor]:
        """``(z, kl)``: eq. 3.15 ``z = softmax((l + g) / tau)`` per variable and
        KL(q || uniform categorical) per sentence and variable ``(B, vars)``; or
        ``mu + sigma eps`` and KL(q || N(0, I)) per sentence and dimension ``(B, dim)``."""
        if self.kind == "gumbel":
            logits = self.head(h).view(len(h), self.vars, self.classes)
            logq = F.log_softmax(logits, -1)
            kl = (logq.exp() * (logq + math.log(self.classes))).sum(2)
            return gumbel_softmax(logits, tau).flatten(1), kl
        mu, logvar = self.head(h).chunk(2, 1)
        z = mu + torch.randn_like(mu) * (0.5 * logvar).exp()
        return z, 0.5 * (mu.pow(2) + logvar.exp() - 1.0 - logvar)

    def prior(self, n: int, gen: torch.Generator | None = None) -> torch.Tensor:
        """``n`` draws from the prior: one-hot uniform categories, or standard normal."""
        if self.kind == "gumbel":
            cats = torch.randint(self.classes, (n, self.vars), generator=gen)
            return F.one_hot(cats, self.classes).float().flatten(1)
        return torch.randn(n, self.dim, generator=gen)


class QuestionEncoder(nn.Module):
    """E_z: an LSTM from ``(f, 0)`` over the question's words, then :class:`Latent`."""

    def __init__(self, cfg: ModelConfig) -> None:
        super().__init__()
        self.lstm = nn.LSTM(cfg.embed_dim, cfg.feature_dim, batch_first=True)
        self.latent = Latent(cfg.feature_dim, cfg)

    def forward(self, emb: torch.Tensor, lengths: torch.Tensor, f: torch.Tensor, tau: float
                ) -> tuple[torch.Tensor, torch.Tensor]:
        """``(z, kl)`` from the state after position ``lengths - 1`` of ``emb (B, T, E)``."""
        out, _ = self.lstm(emb, (f[None], torch.zeros_like(f)[None]))
        last = out[torch.arange(len(out)), (lengths - 1).clamp(min=0)]
        return self.latent(last, tau)


class MatchDiscriminator(nn.Module):
    """D2: does a question ``(B, T, E)`` (embedded or relaxed) match the image feature f?"""

    def __init__(self, embed_dim: int, channels: int, kernel: int, feature_dim: int) -> None:
        super().__init__()
        self.kernel = kernel
        self.conv = nn.Conv1d(embed_dim, channels, kernel)
        self.lstm = nn.LSTM(channels, feature_dim, batch_first=True)

    def forward(self, emb: torch.Tensor, mask: torch.Tensor, f: torch.Tensor) -> torch.Tensor:
        """Match logits ``(B,)``: the LSTM state at the last real word, dotted with f."""
        x = F.pad((emb * mask[..., None]).transpose(1, 2), (0, self.kernel - 1))
        out, _ = self.lstm(F.relu(self.conv(x)).transpose(1, 2))
        last = (mask.sum(1).long() - 1).clamp(min=0)
        return (out[torch.arange(len(out)), last] * f).sum(1)


class VqgModel(nn.Module):
    """E_I, the shared word embedding, E_z, G and (when enabled) D1 and D2."""

    def __init__(self, vocab: int, cfg: ModelConfig) -> None:
        super().__init__()
        self.cfg = cfg
        self.image = ImageEncoder(cfg)
        self.embedding = nn.Embedding(vocab, cfg.embed_dim, padding_idx=PAD_ID)
        self.encoder = QuestionEncoder(cfg)
        # G's initial state is [z, f]: Generator.initial(z, y) concatenates [z, y]
        self.generator = Generator(cfg.embed_dim, cfg.feature_dim, cfg.latent_dim, vocab)
        self.d1 = (TextCNN(self.generator.hidden, cfg.d1_filters, cfg.d1_kernels, 1,
                           cfg.d1_dropout) if cfg.use_d1 else None)
        self.d2 = (MatchDiscriminator(cfg.embed_dim, cfg.d2_channels, cfg.d2_kernel,
                                      cfg.feature_dim) if cfg.use_d2 else None)

    def generator_parameters(self) -> list[nn.Parameter]:
        """What L_1 trains after pre-training: the projection of E_I, embedding, E_z, G."""
        return [p for n, p in self.named_parameters()
                if not n.startswith(("d1.", "d2.", "image.trunk."))]

    def discriminator_parameters(self) -> list[nn.Parameter]:
        """What L_2 trains: D1 and D2."""
        return [p for n, p in self.named_parameters() if n.startswith(("d1.", "d2."))]

    @torch.no_grad()
    def decode(self, f: torch.Tensor, z: torch.Tensor, max_words: int, greedy: bool = True,
               temperature: float = 1.0, gen: torch.Generator | None = None
               ) -> tuple[torch.Tensor, torch.Tensor]:
        """Free-run G from ``[z, f]`` with hard words: ids ``(B, <= max_words + 1)`` ending
        in ``<eos>`` (then ``<pad>``) and the mean log-probability per word ``(B,)``."""
        table = self.embedding.weight
        state = self.generator.initial(z, f)
        x = table[BOS_ID].expand(len(z), -1)
        done = torch.zeros(len(z), dtype=torch.bool)
        ids, total, count = [], torch.zeros(len(z)), torch.zeros(len(z))
        for _ in range(max_words + 1):
            state = self.generator.step(x, state)
            logp = F.log_softmax(self.generator.out(state[0], table) / temperature, -1)
            w = (logp.argmax(1) if greedy
                 else torch.multinomial(logp.exp(), 1, generator=gen)[:, 0])
            live = (~done).float()
            total += logp.gather(1, w[:, None])[:, 0] * live
            count += live
            ids.append(w.masked_fill(done, PAD_ID))
            done |= w == EOS_ID
            if bool(done.all()):
                break
            x = table[w]
        return torch.stack(ids, 1), total / count.clamp(min=1)


# --- losses of eqs. 3.16-3.18 -------------------------------------------------------------

@dataclass
class Forward:
    """One teacher-forced pass: f, eq. 3.16's two terms (batch means; ``kl_loss`` with free
    bits) and G's states."""

    batch: Batch
    f: torch.Tensor
    rec: torch.Tensor
    kl: torch.Tensor
    kl_loss: torch.Tensor
    hidden: torch.Tensor


@dataclass
class Fake:
    """One free-running pass of G from prior codes, with Gumbel-relaxed words."""

    hidden: torch.Tensor
    words: torch.Tensor
    mask: torch.Tensor


def _bce(logits: torch.Tensor, real: bool) -> torch.Tensor:
    target = torch.ones_like(logits) if real else torch.zeros_like(logits)
    return F.binary_cross_entropy_with_logits(logits, target)


def vae_losses(model: VqgModel, batch: Batch, feats: torch.Tensor, tau: float,
               free_nats: float = 0.0) -> Forward:
    """Eq. 3.16 for questions whose images have trunk features ``feats``: summed word NLL
    under G (inputs with word dropout while training) and KL(E_z || prior).

    Free bits (Kingma et al., 2016): ``kl_loss`` counts each latent unit's batch-mean KL as
    at least ``free_nats / units``, so the first ``free_nats`` nats of code are free."""
    table = model.embedding.weight
    f = model.image(feats)
    z, kl = model.encoder(model.embedding(batch.targets), batch.lengths, f, tau)
    inputs = batch.inputs
    if model.training and model.cfg.word_dropout > 0:
        drop = (torch.rand(inputs.shape) < model.cfg.word_dropout) & (inputs > EOS_ID)
        inputs = inputs.masked_fill(drop, UNK_ID)
    hidden, logits = model.generator.teacher_force(model.embedding(inputs), z, f, table)
    kl_loss = kl.mean(0).clamp(min=free_nats / kl.shape[1]).sum()
    return Forward(batch, f, masked_nll(logits, batch.targets).mean(), kl.sum(1).mean(),
                   kl_loss, hidden)


def adversarial_losses(model: VqgModel, out: Forward, tau: float
                       ) -> tuple[Fake | None, dict[str, torch.Tensor]]:
    """The generator side of eqs. 3.17-3.18 (L_G1, L_G2) on a free run of G from prior codes
    with the batch's image features; the fake pass is returned for the discriminator step."""
    if model.d1 is None and model.d2 is None:
        return None, {}
    table = model.embedding.weight
    z = model.encoder.latent.prior(len(out.f))
    hidden, words = model.generator.free_run(model.embedding, table[BOS_ID], z, out.f,
                                             out.batch.inputs.shape[1], tau)
    eos = (words.argmax(-1) == EOS_ID).float()
    mask = ((eos.cumsum(1) - eos) == 0).float()  # up to and including the first <eos>
    losses = {}
    if model.d1 is not None:
        losses["g1"] = _bce(model.d1(hidden, mask)[:, 0], True)
    if model.d2 is not None:
        losses["g2"] = _bce(model.d2(words @ table, mask, out.f), True)
    return Fake(hidden, words, mask), losses


def discriminator_losses(model: VqgModel, out: Forward, fake: Fake) -> dict[str, torch.Tensor]:
    """L_D1 (teacher-forced states real, free-running fake) and L_D2 (true question with its
    image real; generated question, or a true question with another image, fake)."""
    b, losses = out.batch, {}
    if model.d1 is not None:
        losses["d1"] = (_bce(model.d1(out.hidden.detach(), b.mask)[:, 0], True)
                        + _bce(model.d1(fake.hidden.detach(), fake.mask)[:, 0], False))
    if model.d2 is not None:
        table, f = model.embedding.weight.detach(), out.f.detach()
        real = F.embedding(b.targets, table)
        losses["d2"] = (_bce(model.d2(real, b.mask, f), True)
                        + _bce(model.d2(fake.words.detach() @ table, fake.mask, f), False))
        other = b.labels.roll(1) != b.labels
        mismatch = model.d2(real, b.mask, f.roll(1, 0))[other]
        losses["d2_mismatch"] = _bce(mismatch, False) if len(mismatch) else f.new_zeros(())
    return losses
