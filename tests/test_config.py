"""Personality and policy YAML: thesis defaults load, bad files fail naming the key."""

import pytest

from app.cli import main
from core.config_files import ConfigError
from mind.personality import load_personality
from mind.policy.config import load_policy_config


def write(tmp_path, text):
    path = tmp_path / "cfg.yaml"
    path.write_text(text)
    return path


def test_defaults_hold_the_thesis_values():
    p = load_personality()
    assert p.reward.kappa == 1.0 and p.reward.lambda_ == -1.0 and p.reward.nu == 3
    assert p.desired_ranges["survival"] == (0.2, 0.6)
    assert p.mood.threshold == 0.43
    t = load_policy_config().train
    assert (t.gamma, t.learning_rate, t.buffer_size, t.target_sync_updates, t.batch_size) == (
        0.99, 1e-4, 50000, 10000, 32)
    assert t.gamma_steps is None and t.insecure_penalty == 0.0     # the thesis's plain DQN


def test_partial_override_merges_over_defaults(tmp_path):
    p = load_personality(write(tmp_path, "desired_ranges:\n  relationship: [0.3, 0.5]\n"))
    assert p.desired_ranges["relationship"] == (0.3, 0.5)
    assert p.desired_ranges["asking"] == (0.4, 0.6)


@pytest.mark.parametrize(("text", "expected"), [
    ("reward:\n  kapa: 1.0\n", "reward.kapa: unknown key"),
    ("reward:\n  lambda: 0.5\n", "reward.lambda: Input should be less than 0"),
    ("drives:\n  energy: {growth: linear, tau: 8000, grows_during_actions: true}\n",
     "drives.energy: Value error, linear growth needs `rate`"),
    ("desired_ranges:\n  rest: [0.6, 0.4]\n", "desired_ranges: Value error, rest: need"),
    ("mood:\n  drive_weights: {energy: 0.5}\n", "mood.drive_weights: Value error, weights must"),
    ("actions:\n  charge: {drive: battery}\n", "actions.charge.drive"),
    ("- a\n- b\n", "top level must be a mapping"),
    ("reward: [\n", "not valid YAML"),
])
def test_bad_personality_is_rejected_with_its_key(tmp_path, text, expected):
    with pytest.raises(ConfigError) as err:
        load_personality(write(tmp_path, text))
    assert expected in str(err.value)


def test_mood_weights_must_sum_to_one(tmp_path):
    text = "mood:\n  drive_weights: {energy: 0.5, safety_rest: 0.5, belonging: 0.5, " \
           "esteem: 0, self_actualisation: 0, curiosity: 0}\n"
    with pytest.raises(ConfigError, match=r"mood\.drive_weights: .*sum to 1"):
        load_personality(write(tmp_path, text))


def test_bad_policy_config_is_rejected(tmp_path):
    with pytest.raises(ConfigError, match=r"train.batch_size: Input should be greater"):
        load_policy_config(write(tmp_path, "train:\n  batch_size: 0\n"))
    with pytest.raises(ConfigError, match=r"train.insecure_penalty: Input should be less"):
        load_policy_config(write(tmp_path, "train:\n  insecure_penalty: 5\n"))


def test_cli_exits_2_and_names_the_key(tmp_path, capsys):
    path = write(tmp_path, "secure_threshold: 2\n")
    code = main(["eval", "policy", "--personality", str(path), "--episodes", "1",
                 "--out", str(tmp_path / "out")])
    assert code == 2
    assert "secure_threshold: Input should be less than or equal to 1" in capsys.readouterr().err


def test_missing_file_is_reported(tmp_path):
    with pytest.raises(ConfigError, match="file not found"):
        load_personality(tmp_path / "nope.yaml")
