"""The homeostasis equations against values computed by hand from the thesis tables."""

import math

import numpy as np
import pytest

from mind.homeostasis import Homeostasis
from mind.personality import ACTIONS, DRIVES, STAND_BY, load_personality

CHARGE, REST, FIND, DANCE, ASK, CHAT = range(6)


@pytest.fixture(scope="module")
def h() -> Homeostasis:
    return Homeostasis(load_personality())


def test_growth_follows_table_4_1(h):
    d = np.array([0.2, 0.3, 0.4, 0.5, 0.55, 0.6])
    after = h.step(d, STAND_BY)
    # energy: x = 8000 ln(1.2); delta = f(x + 1) - f(x) = 1.2 (e^(1/8000) - 1)
    assert after[0] == pytest.approx(0.2 + 1.2 * (math.exp(1 / 8000) - 1))
    assert after[1] == pytest.approx(0.3 + 1.3 * (math.exp(1 / 6000) - 1))
    np.testing.assert_allclose(after[2:], d[2:] + 0.0005)
    # a thousand steps of growth in one call equal a thousand single steps
    many = d.copy()
    for _ in range(1000):
        many = h.grow(many)
    np.testing.assert_allclose(h.grow(d, 1000), np.minimum(many, 1.0))


def test_actions_follow_table_4_2(h):
    d = np.full(6, 0.7)
    for action, drive, total, steps in [(CHARGE, 0, 0.4, 1000), (REST, 1, 0.15, 100),
                                        (FIND, 2, 0.1, 30), (DANCE, 3, 0.1, 30),
                                        (CHAT, 4, 0.1, 30), (ASK, 5, 0.1, 30)]:
        assert h.duration[action] == steps
        x = d.copy()
        for _ in range(steps):
            x = h.step(x, action)
        assert x[drive] == pytest.approx(0.7 - total)
    assert h.duration[STAND_BY] == 12


def test_busy_robot_keeps_physical_needs_growing(h):
    d = np.full(6, 0.5)
    x = h.step(d, FIND)
    assert x[0] > 0.5 and x[1] > 0.5          # energy and safety/rest grow meanwhile
    np.testing.assert_allclose(x[[3, 4, 5]], 0.5)  # social needs wait
    x = h.step(d, CHARGE)
    assert x[0] == pytest.approx(0.5 - 0.4 / 1000)  # the served drive does not grow


def test_drives_stay_in_unit_interval(h):
    assert h.step(np.full(6, 0.9999), STAND_BY).max() == 1.0
    assert h.step(np.zeros(6), CHARGE).min() == 0.0


def test_motivations_follow_table_4_3(h):
    d = np.full(6, 0.5)
    # overheat, human present, no encouragement
    m = h.motivations(d, [1, 1, 0])
    np.testing.assert_allclose(m, [0.5, 0.6, 0.55, 0.6, 0.6, 0.6])
    # no stimulus at all
    m = h.motivations(d, [0, 0, 0])
    np.testing.assert_allclose(m, [0.5, 0.5, 0.6, 0.55, 0.55, 0.55])
    # human and encouragement: only the human terms remain
    m = h.motivations(d, [0, 1, 1])
    np.testing.assert_allclose(m, [0.5, 0.5, 0.5, 0.55, 0.55, 0.55])


def test_reward_follows_eq_3_7(h):
    before = np.array([0.3, 0.5, 0.5, 0.5, 0.55, 0.5])
    # thesis example: motivation lands at 0.5 in [0.4, 0.6] -> kappa (1 + 0.5 - 0.6) = 0.9
    after = before.copy()
    after[4] = 0.45
    assert h.reward(CHAT, before, after) == pytest.approx(1 + 0.45 - 0.6)
    # acted on a motivation that was above range: positive even if still above
    before2 = before.copy()
    before2[5] = 0.8
    after2 = before2.copy()
    after2[5] = 0.7
    assert h.reward(ASK, before2, after2) == pytest.approx(1 + 0.7 - 0.6)
    # acted without need and pushed it below range: lambda (1 - (m - upper))
    after3 = before.copy()
    after3[2] = 0.35
    assert h.reward(FIND, before, after3) == pytest.approx(-1.0 * (1 - (0.35 - 0.6)))
    # stand-by: +1 when more than nu = 3 motivations are in range, else -1
    assert h.reward(STAND_BY, before, np.array([0.3, 0.5, 0.5, 0.5, 0.9, 0.9])) == 1.0
    assert h.reward(STAND_BY, before, np.array([0.1, 0.5, 0.5, 0.5, 0.9, 0.9])) == -1.0
    # external feedback adds to the internal reward; batched calls agree
    assert h.reward(STAND_BY, before, before, external=-1) == 0.0
    batch = h.reward(np.array([CHAT, STAND_BY]), np.stack([before, before]),
                     np.stack([after, before]))
    np.testing.assert_allclose(batch, [0.85, 1.0])


def test_secure_rate_indicator(h):
    assert h.secure(np.full(6, 0.89))
    assert not h.secure(np.array([0.1, 0.1, 0.9, 0.1, 0.1, 0.1]))
    np.testing.assert_array_equal(h.secure(np.array([[0.1] * 6, [0.95] * 6])), [True, False])


def test_mood_follows_eq_3_6(h):
    d = np.array([0.4, 0.4, 0.5, 0.5, 0.5, 0.5])
    v = 0.25 * 0.4 + 0.25 * 0.4 + 0.2 * 0.5 + 0.1 * 0.5 * 3  # 0.45
    assert h.mood_value(d, 0) == pytest.approx(v)
    assert not h.mood_positive(h.mood_value(d, 0))            # 0.45 > 0.43: negative
    assert h.mood_positive(h.mood_value(d, 1))                # encouragement: 0.35
    assert h.mood_value(d, 0, emotion=1) == pytest.approx(v + 0.1)   # teases a happy person
    assert h.mood_positive(h.mood_value(d, 0, emotion=-1))    # cheers up a sad one


def test_names_line_up():
    assert len(DRIVES) == 6 and len(ACTIONS) == 7 and ACTIONS[STAND_BY] == "stand_by"
