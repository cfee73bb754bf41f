"""Learning from demonstrations (DQfD, Hester et al., 2018) for the policy's DQN.

The homeostatic rule plays seeded training episodes; its transitions stay in a replay
memory of their own for the whole run. The DQN is first trained on them alone (the TD
loss plus a large-margin loss that puts the rule's action ``margin`` above every other
action's value), then, while it collects its own experience, every batch mixes in a share
of demonstrations with the margin loss still on them. Off by default
(``train.demo_transitions: 0``); docs/homeostasis.md has the measured effect.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import torch

from mind.homeostasis import Homeostasis
from mind.personality import MOTIVATIONS
from mind.policy.config import EnvConfig, TrainConfig
from mind.policy.training.baselines import HomeostaticRule
from mind.policy.training.env import Decisions, VecHomeostasisEnv
from mind.policy.training.replay import NStepWriter, ReplayBuffer


def collect_demonstrations(homeostasis: Homeostasis, env_cfg: EnvConfig, tc: TrainConfig,
                           reward_fn: Callable[[Decisions], np.ndarray],
                           discounts: np.ndarray) -> ReplayBuffer:
    """``tc.demo_transitions`` transitions of the homeostatic rule in ``tc.num_envs`` training
    episodes seeded by ``tc.demo_seed``; ``reward_fn(decisions)`` gives the stored reward and
    ``discounts`` each action's discount (stored as ``tc.n_step``-step returns).
    With ``tc.demo_past_insecure`` those episodes do not end when a drive reaches the secure
    threshold, and ``tc.demo_initial_drives`` may start them higher than the DQN's own, so
    that the memory also shows the rule bringing drives back from there.
    ``tc.demo_anticipation`` lets the rule serve some motivations before they leave their
    desired range (:class:`~mind.policy.training.baselines.HomeostaticRule`)."""
    if tc.demo_past_insecure:
        env_cfg = env_cfg.model_copy(update={"terminate_on_insecure": False})
    if tc.demo_initial_drives is not None:
        env_cfg = env_cfg.model_copy(update={"initial_drives": tc.demo_initial_drives})
    env = VecHomeostasisEnv(homeostasis, env_cfg, tc.num_envs, seed=tc.demo_seed)
    rule = HomeostaticRule(homeostasis, tc.demo_anticipation)
    memory = ReplayBuffer(tc.demo_transitions, len(MOTIVATIONS))
    writer = NStepWriter(memory, tc.n_step, tc.num_envs, len(MOTIVATIONS), discounts)
    every = np.arange(tc.num_envs)
    env.act(every, rule(env.observe(every)))
    while memory.size < tc.demo_transitions:
        d = env.advance()
        # becoming insecure ends what the DQN learns from (as in its own episodes), even
        # where the demonstration goes on from there
        writer.add(d, reward_fn(d), d.terminal | d.became_insecure)
        env.act(d.idx, rule(d.decide_obs))
    return memory


def margin_loss(q_obs: torch.Tensor, expert: torch.Tensor, margin: float) -> torch.Tensor:
    """DQfD's supervised loss: mean of ``max_a [Q(s, a) + margin * (a != a_E)] - Q(s, a_E)``."""
    penalty = torch.full_like(q_obs, margin).scatter(1, expert[:, None], 0.0)
    q_expert = q_obs.gather(1, expert[:, None]).squeeze(1)
    return ((q_obs + penalty).max(dim=1).values - q_expert).mean()
