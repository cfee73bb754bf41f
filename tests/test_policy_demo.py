"""Learning from the homeostatic rule's demonstrations and the network's input scaling."""

import numpy as np
import pytest
import torch

from app.homeostasis import Homeostasis
from app.personality import STAND_BY, load_personality
from app.policy.baselines import HomeostaticRule
from app.policy.config import load_policy_config
from app.policy.demo import collect_demonstrations, margin_loss
from app.policy.network import DuelingQNetwork
from app.policy.train import train


@pytest.fixture(scope="module")
def h():
    return Homeostasis(load_personality())


@pytest.fixture(scope="module")
def cfg():
    return load_policy_config()


def test_margin_loss_by_hand():
    q = torch.tensor([[1.0, 2.0, 0.0], [3.0, 1.0, 0.5]])
    expert = torch.tensor([0, 0])
    # row 1: max(1, 2 + 0.8, 0 + 0.8) - 1 = 1.8; row 2: the expert leads by more than 0.8: 0
    assert margin_loss(q, expert, 0.8).item() == pytest.approx(0.9)


def test_demonstrations_are_the_rules_choices(h, cfg):
    tc = cfg.train.model_copy(update={"num_envs": 8, "demo_transitions": 500})
    demos = collect_demonstrations(h, cfg.env, tc, lambda d: d.reward)
    assert demos.size == 500
    np.testing.assert_array_equal(demos.action, HomeostaticRule(h)(demos.obs))
    assert len(set(demos.action.tolist())) >= 4  # the rule acts, it does not only stand by


def test_input_scaling_is_an_affine_map_of_the_motivations():
    scaled = DuelingQNetwork(6, 7, [16], 8, input_offset=0.6, input_scale=0.05)
    plain = DuelingQNetwork(6, 7, [16], 8)
    plain.load_state_dict(scaled.state_dict())
    obs = torch.rand(4, 6)
    torch.testing.assert_close(scaled(obs), plain((obs - 0.6) / 0.05))


def test_pretraining_on_demonstrations_imitates_the_rule(h, cfg, tmp_path):
    tiny = cfg.model_copy(update={
        "network": cfg.network.model_copy(update={
            "hidden": [64, 64], "head": 32, "input_offset": 0.6, "input_scale": 0.05}),
        "train": cfg.train.model_copy(update={
            "num_envs": 32, "total_transitions": 1, "learning_rate": 1e-3, "batch_size": 128,
            "target_sync_updates": 200, "checkpoint_every": 5000, "eval_every": 5000,
            "demo_transitions": 6000, "demo_pretrain_updates": 3000, "demo_weight": 10.0})})
    train(h.personality, tiny, tmp_path, progress=False)
    blob = torch.load(tmp_path / "checkpoint.pt", weights_only=False)
    q = DuelingQNetwork(6, 7, **tiny.network.model_dump())
    q.load_state_dict(blob["q"])
    fresh = collect_demonstrations(h, cfg.env, tiny.train.model_copy(
        update={"demo_seed": 7, "demo_transitions": 3000}), lambda d: d.reward)
    with torch.no_grad():
        agree = (q(torch.as_tensor(fresh.obs)).argmax(1).numpy() == fresh.action).mean()
    share_stand_by = (fresh.action == STAND_BY).mean()
    assert agree >= 0.95 > share_stand_by
