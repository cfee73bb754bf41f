"""The replay memory and the n-step returns written into it, against hand-computed values."""

from __future__ import annotations

import numpy as np
import pytest

from mind.policy.training.env import Decisions
from mind.policy.training.replay import NStepWriter, ReplayBuffer


def feed(writer: NStepWriter, steps: list[tuple[float, float, bool, bool]], start: int = 0
         ) -> None:
    """Decisions ``start``, ``start + 1``, ... of env 0 (of 2): (reward, discount, terminal,
    ended); decision k goes from obs [k, 0] to [k + 1, 0]."""
    for k, (r, g, terminal, ended) in enumerate(steps, start):
        writer.discounts[k % 3] = g  # action k % 3 is the one taken; its discount is g
        nxt = np.array([[k + 1, 0.0]])
        d = Decisions(np.array([0]), np.array([[k, 0.0]]), np.array([k % 3]), np.array([r]),
                      nxt, nxt, np.array([terminal]), np.array([False]),
                      ended=np.array([0] if ended else [], dtype=np.int64))
        writer.add(d, np.array([r]), np.array([terminal]))


def written(memory: ReplayBuffer) -> list[tuple]:
    n = memory.size
    return [(float(memory.obs[i, 0]), float(memory.reward[i]), float(memory.next_obs[i, 0]),
             float(memory.discount[i]), bool(memory.terminal[i])) for i in range(n)]


def test_one_step_writes_each_decision_as_it_comes():
    memory = ReplayBuffer(10, 2)
    feed(NStepWriter(memory, 1, 2, 2, np.zeros(3)),
         [(1.0, 0.9, False, False), (2.0, 0.5, True, True)])
    assert written(memory) == [(0.0, 1.0, 1.0, pytest.approx(0.9), False),
                               (1.0, 2.0, 2.0, 0.5, True)]


def test_three_step_returns_discount_each_reward_by_the_actions_before_it():
    memory = ReplayBuffer(10, 2)
    writer = NStepWriter(memory, 3, 2, 2, np.zeros(3))
    feed(writer, [(1.0, 0.5, False, False), (2.0, 0.5, False, False)])
    assert memory.size == 0  # nothing is complete yet
    feed(writer, [(4.0, 0.5, False, False)], start=2)
    # 1 + 0.5 * 2 + 0.25 * 4 = 3, bootstrapping from obs 3 with 0.5^3
    assert written(memory) == [(0.0, 3.0, 3.0, 0.125, False)]
    np.testing.assert_array_equal(memory.action[:1], [0])


def test_a_terminal_decision_writes_everything_pending_without_bootstrap():
    memory = ReplayBuffer(10, 2)
    feed(NStepWriter(memory, 3, 2, 2, np.zeros(3)),
         [(1.0, 0.5, False, False), (2.0, 0.5, False, False), (-10.0, 0.5, True, False)])
    rows = written(memory)
    assert [r[1] for r in rows] == [1.0 + 1.0 - 2.5, 2.0 - 5.0, -10.0]
    assert all(r[4] for r in rows) and [r[2] for r in rows] == [3.0, 3.0, 3.0]


def test_the_end_of_an_episode_bootstraps_the_shorter_returns():
    memory = ReplayBuffer(10, 2)
    writer = NStepWriter(memory, 3, 2, 2, np.zeros(3))
    feed(writer, [(1.0, 0.5, False, False), (2.0, 0.5, False, True)])
    assert written(memory) == [(0.0, 2.0, 2.0, 0.25, False), (1.0, 2.0, 2.0, 0.5, False)]
    feed(writer, [(7.0, 0.5, False, False)], start=2)  # a new episode starts from nothing pending
    assert memory.size == 2 and writer.count[0] == 1


def test_a_memory_missing_a_field_is_refused():
    state = ReplayBuffer(4, 2).state_dict()
    del state["discount"]
    with pytest.raises(KeyError, match="discount"):
        ReplayBuffer(4, 2).load_state_dict(state)
