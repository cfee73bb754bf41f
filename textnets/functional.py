"""Small functions shared by the text networks: the masked sentence loss, the Gumbel-softmax
relaxation (thesis eq. 3.12) and its temperature schedule."""

from __future__ import annotations

import torch
import torch.nn.functional as F  # noqa: N812

from textnets.vocab import PAD_ID


def masked_nll(logits: torch.Tensor, targets: torch.Tensor) -> torch.Tensor:
    """Summed token cross-entropy per sentence ``(B,)``; ``<pad>`` targets count zero."""
    nll = F.cross_entropy(logits.reshape(-1, logits.shape[-1]), targets.reshape(-1),
                          ignore_index=PAD_ID, reduction="none")
    return nll.view(targets.shape).sum(1)


def gumbel_softmax(logits: torch.Tensor, tau: float) -> torch.Tensor:
    """Eq. 3.12: ``softmax((p + G) / tau)`` with ``G = -log(-log(U))``, ``U ~ Unif(0, 1)``."""
    u = torch.rand_like(logits).clamp_(min=1e-10)
    return torch.softmax((logits - u.log_().neg_().log_()) / tau, -1)


def temperature(step: int, start: float, decay: float, every: int, floor: float) -> float:
    """Gumbel-softmax temperature ``start * decay ** (step // every)``, at least ``floor``."""
    return max(floor, start * decay ** (step // every))
