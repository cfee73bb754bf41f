"""Uniform experience replay for the DQN, stored in flat numpy arrays."""

from __future__ import annotations

import numpy as np


class ReplayBuffer:
    """A ring buffer of (obs, action, reward, next_obs, terminal) transitions."""

    def __init__(self, capacity: int, obs_dim: int) -> None:
        self.capacity = capacity
        self.obs = np.zeros((capacity, obs_dim), dtype=np.float32)
        self.next_obs = np.zeros((capacity, obs_dim), dtype=np.float32)
        self.action = np.zeros(capacity, dtype=np.int64)
        self.reward = np.zeros(capacity, dtype=np.float32)
        self.terminal = np.zeros(capacity, dtype=np.float32)
        self.pos = 0
        self.size = 0

    def add(self, obs: np.ndarray, action: np.ndarray, reward: np.ndarray,
            next_obs: np.ndarray, terminal: np.ndarray) -> None:
        """Append a batch of transitions, overwriting the oldest when full."""
        idx = (self.pos + np.arange(len(action))) % self.capacity
        self.obs[idx], self.action[idx] = obs, action
        self.reward[idx], self.next_obs[idx] = reward, next_obs
        self.terminal[idx] = terminal
        self.pos = int((self.pos + len(action)) % self.capacity)
        self.size = min(self.size + len(action), self.capacity)

    def sample(self, rng: np.random.Generator, batch_size: int) -> tuple[np.ndarray, ...]:
        """A uniformly sampled mini-batch."""
        i = rng.integers(0, self.size, size=batch_size)
        return self.obs[i], self.action[i], self.reward[i], self.next_obs[i], self.terminal[i]

    def state_dict(self) -> dict:
        """Everything needed to resume training with the same memory."""
        return {k: getattr(self, k) for k in ("obs", "next_obs", "action", "reward", "terminal",
                                              "pos", "size")}

    def load_state_dict(self, state: dict) -> None:
        """Restore from :meth:`state_dict`."""
        for k, v in state.items():
            setattr(self, k, v)
