"""Kim's TextCNN over a masked sequence of vectors: the discriminator of style transfer (over
the generator's hidden states, eq. 3.13) and of VQG, and, with its own embedding, the
sentiment judge of the style evaluation."""

from __future__ import annotations

import torch
import torch.nn.functional as F  # noqa: N812
from torch import nn


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
