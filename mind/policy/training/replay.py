"""Experience replay for the DQN, stored in flat numpy arrays, and the n-step returns
written into it."""

from __future__ import annotations

import numpy as np

from mind.policy.training.env import Decisions

FIELDS = ("obs", "next_obs", "action", "reward", "discount", "terminal")


class ReplayBuffer:
    """A ring buffer of (obs, action, reward, next_obs, discount, terminal) transitions;
    ``discount`` is what the value of ``next_obs`` is multiplied by in the target."""

    def __init__(self, capacity: int, obs_dim: int) -> None:
        self.capacity = capacity
        self.obs = np.zeros((capacity, obs_dim), dtype=np.float32)
        self.next_obs = np.zeros((capacity, obs_dim), dtype=np.float32)
        self.action = np.zeros(capacity, dtype=np.int64)
        self.reward = np.zeros(capacity, dtype=np.float32)
        self.discount = np.zeros(capacity, dtype=np.float32)
        self.terminal = np.zeros(capacity, dtype=np.float32)
        self.pos = 0
        self.size = 0

    def add(self, obs: np.ndarray, action: np.ndarray, reward: np.ndarray,
            next_obs: np.ndarray, discount: np.ndarray, terminal: np.ndarray) -> None:
        """Append a batch of transitions, overwriting the oldest when full."""
        idx = (self.pos + np.arange(len(action))) % self.capacity
        self.obs[idx], self.action[idx] = obs, action
        self.reward[idx], self.next_obs[idx] = reward, next_obs
        self.discount[idx], self.terminal[idx] = discount, terminal
        self.pos = int((self.pos + len(action)) % self.capacity)
        self.size = min(self.size + len(action), self.capacity)

    def sample(self, rng: np.random.Generator, batch_size: int) -> tuple[np.ndarray, ...]:
        """A uniformly sampled mini-batch: obs, action, reward, next_obs, discount, terminal."""
        i = rng.integers(0, self.size, size=batch_size)
        return (self.obs[i], self.action[i], self.reward[i], self.next_obs[i],
                self.discount[i], self.terminal[i])

    def state_dict(self) -> dict:
        """Everything needed to resume training with the same memory."""
        return {k: getattr(self, k) for k in (*FIELDS, "pos", "size")}

    def load_state_dict(self, state: dict) -> None:
        """Restore from :meth:`state_dict`; a memory without every field is refused."""
        missing = [k for k in (*FIELDS, "pos", "size") if k not in state]
        if missing:
            raise KeyError(f"replay memory lacks {', '.join(missing)}")
        for k, v in state.items():
            setattr(self, k, v)


class NStepWriter:
    """Turns each env's stream of decisions into n-step transitions for a replay memory
    (Sutton & Barto §7.1; DQfD and Rainbow use them): the stored reward sums the next ``n``
    rewards, each discounted by the actions before it, and the target bootstraps from the
    state ``n`` decisions later. A terminal transition, or the end of an episode, writes
    everything still pending (shorter returns; no bootstrap after a terminal one). With
    ``n = 1`` every decision is written as it comes. ``discounts[a]`` is action a's
    discount (``mind.policy.training.train.action_discounts``)."""

    def __init__(self, memory: ReplayBuffer, n: int, num_envs: int, obs_dim: int,
                 discounts: np.ndarray) -> None:
        self.memory, self.n, self.discounts = memory, n, discounts
        self.obs = np.zeros((num_envs, n, obs_dim), dtype=np.float32)
        self.action = np.zeros((num_envs, n), dtype=np.int64)
        self.reward = np.zeros((num_envs, n))
        self.discount = np.zeros((num_envs, n))
        self.count = np.zeros(num_envs, dtype=np.int64)

    def add(self, d: Decisions, reward: np.ndarray, terminal: np.ndarray) -> None:
        """The decisions that just finished, stored with ``reward``; ``terminal`` marks
        those that must not bootstrap. Envs in ``d.ended`` start a new episode after them."""
        idx, next_obs = d.idx, d.next_obs
        ended = np.isin(idx, d.ended)
        k = self.count[idx]
        self.obs[idx, k], self.action[idx, k] = d.obs, d.action
        self.reward[idx, k], self.discount[idx, k] = reward, self.discounts[d.action]
        self.count[idx] += 1
        for j, i in enumerate(idx):
            if terminal[j] or ended[j]:
                self._write(i, self.count[i], next_obs[j], bool(terminal[j]))
                self.count[i] = 0
            elif self.count[i] == self.n:
                self._write(i, 1, next_obs[j], False)
                self._shift(i)

    def _write(self, i: int, first: int, bootstrap: np.ndarray, terminal: bool) -> None:
        """Write env ``i``'s ``first`` oldest pending decisions, each with the return of
        every pending decision from it on and the discount to ``bootstrap``."""
        c = self.count[i]
        r, g = self.reward[i, :c], self.discount[i, :c]
        returns, discounts = np.zeros(first), np.zeros(first)
        for s in range(first):
            weights = np.concatenate([[1.0], np.cumprod(g[s:c - 1])])
            returns[s] = weights @ r[s:c]
            discounts[s] = np.prod(g[s:c])
        self.memory.add(self.obs[i, :first], self.action[i, :first], returns,
                        np.broadcast_to(bootstrap, (first, bootstrap.shape[-1])), discounts,
                        np.full(first, float(terminal)))

    def _shift(self, i: int) -> None:
        """Drop env ``i``'s oldest pending decision."""
        for buf in (self.obs, self.action, self.reward, self.discount):
            buf[i, :-1] = buf[i, 1:].copy()
        self.count[i] -= 1
