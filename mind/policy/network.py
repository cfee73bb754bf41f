"""The dueling Q-network (thesis Fig. 3.6): a shared trunk, a state value and action advantages."""

from __future__ import annotations

import torch
from torch import nn


class DuelingQNetwork(nn.Module):
    """Q(s, a) = V(s) + A(s, a) - mean_a' A(s, a') over fully connected layers.

    The observation enters as ``(obs - input_offset) / input_scale``: the defaults pass the
    motivations through unchanged; a narrow scale lets the first layer resolve the small
    differences around the desired ranges that decide between acting and standing by."""

    def __init__(self, n_obs: int, n_actions: int, hidden: list[int], head: int,
                 init_std: float = 0.02, input_offset: float = 0.0,
                 input_scale: float = 1.0) -> None:
        super().__init__()
        self.input_offset, self.input_scale = input_offset, input_scale
        layers: list[nn.Module] = []
        width = n_obs
        for size in hidden:
            layers += [nn.Linear(width, size), nn.ReLU()]
            width = size
        self.trunk = nn.Sequential(*layers)
        self.value = nn.Sequential(nn.Linear(width, head), nn.ReLU(), nn.Linear(head, 1))
        self.advantage = nn.Sequential(nn.Linear(width, head), nn.ReLU(),
                                       nn.Linear(head, n_actions))
        for module in self.modules():
            if isinstance(module, nn.Linear):
                nn.init.normal_(module.weight, 0.0, init_std)
                nn.init.zeros_(module.bias)

    def forward(self, obs: torch.Tensor) -> torch.Tensor:
        """Q-values, shape (batch, n_actions)."""
        h = self.trunk((obs - self.input_offset) / self.input_scale)
        adv = self.advantage(h)
        return self.value(h) + adv - adv.mean(dim=-1, keepdim=True)
