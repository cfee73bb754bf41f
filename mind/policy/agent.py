"""The trained decision maker: loads a shipped policy file and picks actions greedily."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import torch

from core.checkpoint import read_weights
from core.errors import UserError
from mind.personality import ACTIONS, MOTIVATIONS
from mind.policy.config import DEFAULT_POLICY
from mind.policy.network import DuelingQNetwork


class PolicyFileError(UserError):
    """A policy file is missing, unreadable or does not match the expected shapes."""


class DQNPolicy:
    """``Policy.act(motivations) -> action`` backed by a dueling Q-network."""

    def __init__(self, net: DuelingQNetwork) -> None:
        self.net = net.eval()

    @classmethod
    def load(cls, path: str | Path = DEFAULT_POLICY) -> DQNPolicy:
        """Load weights written by :func:`mind.policy.training.train.export_policy`."""
        blob = read_weights(path, PolicyFileError, "train one with `companion train policy`")
        try:
            net = DuelingQNetwork(len(MOTIVATIONS), len(ACTIONS), **blob["network"])
            net.load_state_dict(blob["state_dict"])
        except Exception as exc:  # any corruption or mismatch ends up here
            raise PolicyFileError(f"{path}: not a valid policy file ({exc})") from None
        return cls(net)

    @torch.no_grad()
    def q_values(self, motivations: np.ndarray) -> np.ndarray:
        """Q-values for a batch (N, 6) or a single (6,) vector of motivations."""
        obs = torch.as_tensor(np.asarray(motivations, dtype=np.float32))
        return self.net(obs.reshape(-1, len(MOTIVATIONS))).numpy().reshape(
            *obs.shape[:-1], len(ACTIONS))

    def __call__(self, motivations: np.ndarray) -> np.ndarray:
        """Greedy actions for a batch of motivations."""
        return self.q_values(motivations).argmax(axis=-1)

    def act(self, motivations: np.ndarray) -> str:
        """The name of the action to take for one robot's motivations."""
        return ACTIONS[int(self(np.asarray(motivations)[None])[0])]
