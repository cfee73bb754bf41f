"""The evaluation networks: a TextCNN sentiment classifier and an LSTM language model.

Both are trained on the training split only; the classifier measures transfer accuracy and
the language model the fluency (perplexity, thesis eq. 4.2) of transferred sentences.
"""

from __future__ import annotations

import torch
import torch.nn.functional as F  # noqa: N812
from torch import nn

from dialogue.style.config import ClassifierConfig, LMConfig
from dialogue.style.model import N_STYLES
from textnets.batch import Batch
from textnets.functional import masked_nll
from textnets.generator import TiedOutput
from textnets.textcnn import TextCNN
from textnets.vocab import PAD_ID


class SentimentClassifier(nn.Module):
    """Word embedding + TextCNN -> logits over {negative, positive}."""

    def __init__(self, vocab: int, cfg: ClassifierConfig) -> None:
        super().__init__()
        self.embedding = nn.Embedding(vocab, cfg.embed_dim, padding_idx=PAD_ID)
        self.cnn = TextCNN(cfg.embed_dim, cfg.filters, cfg.kernels, N_STYLES, cfg.dropout)

    def forward(self, batch: Batch) -> torch.Tensor:
        """Logits ``(B, 2)``; the classifier reads ``w_1 .. w_n <eos>`` (the targets)."""
        return self.cnn(self.embedding(batch.targets), batch.mask)

    def loss(self, batch: Batch) -> torch.Tensor:
        """Mean cross-entropy against the batch labels."""
        return F.cross_entropy(self(batch), batch.labels)


class LanguageModel(nn.Module):
    """A one-layer LSTM language model over both styles (output tied to the embedding)."""

    def __init__(self, vocab: int, cfg: LMConfig) -> None:
        super().__init__()
        self.embedding = nn.Embedding(vocab, cfg.embed_dim, padding_idx=PAD_ID)
        self.drop = nn.Dropout(cfg.dropout)
        self.lstm = nn.LSTM(cfg.embed_dim, cfg.hidden, batch_first=True)
        self.out = TiedOutput(cfg.hidden, cfg.embed_dim, vocab)

    def forward(self, batch: Batch) -> torch.Tensor:
        """Summed next-word negative log-likelihood per sentence ``(B,)`` (``<eos>`` counted)."""
        hidden, _ = self.lstm(self.drop(self.embedding(batch.inputs)))
        return masked_nll(self.out(self.drop(hidden), self.embedding.weight), batch.targets)

    def loss(self, batch: Batch) -> torch.Tensor:
        """Mean per-token negative log-likelihood."""
        return self(batch).sum() / batch.mask.sum()
