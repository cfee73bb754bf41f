"""The training env, a tiny seeded training run, the baselines, learning from the rule's
demonstrations, input scaling and the shipped policy."""

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import torch

from app.cli import main
from core.checkpoint import claim_run_folder, read_checkpoint
from core.config_files import ConfigError
from core.errors import UserError
from mind.homeostasis import Homeostasis
from mind.personality import ACTIONS, STAND_BY, load_personality
from mind.policy.agent import DQNPolicy, PolicyFileError
from mind.policy.config import DEFAULT_POLICY, load_policy_config
from mind.policy.network import DuelingQNetwork
from mind.policy.training.baselines import HomeostaticRule, RandomPolicy
from mind.policy.training.demo import collect_demonstrations, margin_loss
from mind.policy.training.env import Decisions, VecHomeostasisEnv
from mind.policy.training.evaluate import run_episodes, summarise
from mind.policy.training.train import action_discounts, selection_score, train, training_reward

DISCOUNTS = np.full(len(ACTIONS), 0.99, dtype=np.float32)  # per decision, every action


@pytest.fixture(scope="module")
def h():
    return Homeostasis(load_personality())


@pytest.fixture(scope="module")
def cfg():
    return load_policy_config()


def short_env(cfg, steps=2000):
    return cfg.env.model_copy(update={"episode_steps": steps})


def test_env_runs_actions_for_their_duration(h, cfg):
    env = VecHomeostasisEnv(h, cfg.env, 3, seed=0)
    env.act(np.arange(3), np.array([2, STAND_BY, 0]))  # find people, stand by, charge
    d = env.advance()
    assert list(d.idx) == [1] and env.t[1] == 12        # stand-by ends first, after 12 steps
    env.act(d.idx, np.array([STAND_BY]))
    assert list(env.advance().idx) == [1] and env.t[1] == 24   # the second stand-by
    env.act(np.array([1]), np.array([STAND_BY]))
    assert list(env.advance().idx) == [0] and env.t[0] == 30   # find people took 30 steps


def test_env_is_seeded(h, cfg):
    a = run_episodes(HomeostaticRule(h), h, short_env(cfg), 4, seed=3)[0]
    b = run_episodes(HomeostaticRule(h), h, short_env(cfg), 4, seed=3)[0]
    assert a == b


def test_env_state_round_trips(h, cfg):
    env = VecHomeostasisEnv(h, cfg.env, 4, seed=0)
    rule = HomeostaticRule(h)
    env.act(np.arange(4), rule(env.observe()))
    twin = VecHomeostasisEnv(h, cfg.env, 4, seed=99)
    twin.load_state_dict(env.state_dict())
    for e in (env, twin):
        d = e.advance()
        e.act(d.idx, rule(d.decide_obs))
    np.testing.assert_array_equal(env.drives, twin.drives)


def test_rule_serves_the_strongest_motivation_above_range(h):
    rule = HomeostaticRule(h)
    m = np.array([[0.5, 0.5, 0.5, 0.5, 0.5, 0.5],    # all in range: stand by
                  [0.7, 0.5, 0.65, 0.5, 0.5, 0.5],   # survival strongest and above: charge
                  [0.1, 0.5, 0.5, 0.5, 0.62, 0.5]])  # self-actualisation: chat
    assert [ACTIONS[a] for a in rule(m)] == ["stand_by", "charge", "chat"]


def test_anticipating_rule_serves_before_the_bound(h):
    """Within the anticipation of its upper bound a motivation is served; others are not."""
    rule = HomeostaticRule(h, {"social_interaction": 0.02})
    m = np.array([[0.1, 0.5, 0.5, 0.5, 0.59, 0.5],    # social 0.01 below its bound: chat
                  [0.1, 0.5, 0.5, 0.5, 0.57, 0.5],    # 0.03 below: stand by
                  [0.1, 0.59, 0.5, 0.5, 0.5, 0.5]])   # rest is not anticipated: stand by
    assert [ACTIONS[a] for a in rule(m)] == ["chat", "stand_by", "stand_by"]
    assert ACTIONS[HomeostaticRule(h)(m[:1])[0]] == "stand_by"


def test_dueling_network_shapes_and_init():
    net = DuelingQNetwork(6, 7, [32, 32], 16, init_std=0.02)
    q = net(torch.zeros(5, 6))
    assert q.shape == (5, 7)
    first = net.trunk[0].weight
    assert abs(first.std().item() - 0.02) < 0.01 and first.abs().max() < 0.2


def test_tiny_training_run_beats_random(h, cfg, tmp_path):
    tiny = cfg.model_copy(update={
        "env": short_env(cfg, 3000),
        "network": cfg.network.model_copy(update={"hidden": [64, 64], "head": 32}),
        "train": cfg.train.model_copy(update={
            "num_envs": 32, "total_transitions": 20000, "learning_starts": 1000,
            "updates_per_transition": 0.5, "target_sync_updates": 500, "buffer_size": 20000,
            "learning_rate": 1e-3, "exploration_fraction": 0.5, "checkpoint_every": 2000,
            "eval_every": 5000, "eval_episodes": 8})})
    summary = train(h.personality, tiny, tmp_path, progress=False)
    assert summary["transitions"] >= 20000
    assert (tmp_path / "checkpoint.pt").exists() and (tmp_path / "train_log.csv").exists()
    trained = summarise(run_episodes(DQNPolicy.load(tmp_path / "policy.pt"), h, tiny.env,
                                     16, seed=5)[0])
    rand = summarise(run_episodes(RandomPolicy(7, 5), h, tiny.env, 16, seed=5)[0])
    assert trained["mean_reward"] > rand["mean_reward"] + 10  # the objective it optimises


def test_training_refuses_to_overwrite_and_resumes(h, cfg, tmp_path):
    tiny = cfg.model_copy(update={
        "env": short_env(cfg, 500),
        "train": cfg.train.model_copy(update={
            "num_envs": 8, "total_transitions": 600, "learning_starts": 100,
            "checkpoint_every": 50, "eval_episodes": 2})})
    train(h.personality, tiny, tmp_path, progress=False)
    with pytest.raises(FileExistsError, match="--resume"):
        train(h.personality, tiny, tmp_path, progress=False)
    longer = tiny.model_copy(update={
        "train": tiny.train.model_copy(update={"total_transitions": 1200})})
    with pytest.raises(PolicyFileError, match="total_transitions: run has 600, the config"):
        train(h.personality, longer, tmp_path, resume=True, progress=False)
    stored = tmp_path / "resolved_config.yaml"  # a run changed on purpose: its own file
    stored.write_text(stored.read_text().replace("total_transitions: 600",
                                                 "total_transitions: 1200"))
    summary = train(h.personality, longer, tmp_path, resume=True, progress=False)
    assert summary["transitions"] >= 1200
    rows = (tmp_path / "train_log.csv").read_text().splitlines()
    assert rows[0].startswith("transitions,") and len(rows) > 1


def test_resuming_a_checkpoint_of_an_older_version_names_the_file(h, cfg, tmp_path):
    tiny = cfg.model_copy(update={
        "env": short_env(cfg, 500),
        "train": cfg.train.model_copy(update={
            "num_envs": 8, "total_transitions": 300, "learning_starts": 100,
            "checkpoint_every": 20, "eval_episodes": 2})})
    train(h.personality, tiny, tmp_path, progress=False)
    ckpt = tmp_path / "checkpoint.pt"
    state = torch.load(ckpt, weights_only=True)
    del state["env"]["secure_at_choice"]  # as written before the env tracked it
    torch.save(state, ckpt)
    with pytest.raises(PolicyFileError, match=r"checkpoint\.pt: cannot resume .*secure_at_choice"):
        train(h.personality, tiny, tmp_path, resume=True, progress=False)


def test_a_folder_another_live_training_holds_is_refused(tmp_path):
    other = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(30)"])
    try:
        (tmp_path / ".lock").write_text(str(other.pid))
        with pytest.raises(UserError, match=f"process {other.pid} is training"):
            claim_run_folder(tmp_path, tmp_path / "checkpoint.pt", resume=True)
    finally:
        other.kill()
        other.wait()
    claim_run_folder(tmp_path, tmp_path / "checkpoint.pt", resume=True)  # stale: taken over
    assert (tmp_path / ".lock").read_text() == str(os.getpid())


def test_the_lock_goes_when_the_training_process_exits(tmp_path):
    code = ("import sys; from pathlib import Path; "
            "from core.checkpoint import claim_run_folder; "
            "d = Path(sys.argv[1]); claim_run_folder(d, d / 'checkpoint.pt', resume=False); "
            "print((d / '.lock').read_text())")
    done = subprocess.run([sys.executable, "-c", code, str(tmp_path)], capture_output=True,
                          text=True, check=True, cwd=Path(__file__).resolve().parents[1])
    assert done.stdout.strip().isdigit()          # held while it ran
    assert not (tmp_path / ".lock").exists()      # released at exit


def test_insecure_penalty_lands_on_the_terminal_transitions(h, cfg, tmp_path):
    tiny = cfg.model_copy(update={
        "env": short_env(cfg, 500),
        "train": cfg.train.model_copy(update={
            "num_envs": 8, "total_transitions": 600, "learning_starts": 100,
            "checkpoint_every": 50, "eval_episodes": 2, "insecure_penalty": -50.0})})
    train(h.personality, tiny, tmp_path, progress=False)
    memory = read_checkpoint(tmp_path / "checkpoint.pt")["memory"]
    n = memory["size"]
    terminal, reward = memory["terminal"][:n].astype(bool), memory["reward"][:n]
    assert terminal.any() and (~terminal).any()      # random actions reach insecurity often
    assert (reward[terminal] <= -48.0).all() and (reward[~terminal] > -5.0).all()


def test_discount_per_decision_or_per_time():
    durations = np.array([1000, 100, 30, 12])
    np.testing.assert_allclose(action_discounts(0.99, durations, None), np.full(4, 0.99))
    per_time = action_discounts(0.99, durations, 12)
    expected = [0.99 ** (1000 / 12), 0.99 ** (100 / 12), 0.99 ** 2.5, 0.99]
    np.testing.assert_allclose(per_time, expected, rtol=1e-6)
    assert per_time[0] < 0.44  # a charge costs the future as much as 83 stand-bys


def test_training_reward_adds_the_penalty_and_charges_time(cfg):
    durations = np.array([1000, 100, 30, 12])
    z = np.zeros((3, 6))
    became_insecure = np.array([False, False, True])
    d = Decisions(np.arange(3), z, np.array([0, 3, 2]), np.array([0.5, 1.0, 0.9]), z, z,
                  became_insecure, became_insecure)
    assert np.allclose(training_reward(d, durations, cfg.train), [0.5, 1.0, 0.9])  # thesis
    tc = cfg.train.model_copy(update={"insecure_penalty": -100.0, "time_cost": 0.01})
    assert np.allclose(training_reward(d, durations, tc), [0.5 - 10, 1.0 - 0.12, 0.9 - 100.3])


def test_selection_prefers_secure_then_rewarding_policies():
    secure_poor = selection_score({"rsr": 1.0, "mean_reward": 400.0}, 0.9998)
    secure_rich = selection_score({"rsr": 0.9999, "mean_reward": 600.0}, 0.9998)
    insecure_rich = selection_score({"rsr": 0.99, "mean_reward": 900.0}, 0.9998)
    assert secure_rich > secure_poor > insecure_rich


def test_train_cli_writes_logs_plots_and_policy(tmp_path):
    cfg = tmp_path / "tiny.yaml"
    cfg.write_text("env: {episode_steps: 400}\n"
                   "train: {num_envs: 4, episode_steps: 400, total_transitions: 300,\n"
                   "        learning_starts: 50, eval_episodes: 2, checkpoint_every: 100}\n")
    out = tmp_path / "run"
    assert main(["train", "policy", "--config", str(cfg), "--out", str(out),
                 "--no-progress", "--export", str(tmp_path / "exported.pt")]) == 0
    for name in ("checkpoint.pt", "policy.pt", "train_log.csv", "eval_log.csv",
                 "resolved_config.yaml", "summary.json", "plots/training_reward.png"):
        assert (out / name).exists(), name
    DQNPolicy.load(tmp_path / "exported.pt")
    assert main(["train", "policy", "--config", str(cfg), "--out", str(out),
                 "--no-progress"]) == 2  # refuses to overwrite without --resume


def test_missing_or_corrupt_policy_file_is_a_clear_error(tmp_path):
    with pytest.raises(PolicyFileError, match="not found"):
        DQNPolicy.load(tmp_path / "none.pt")
    bad = tmp_path / "bad.pt"
    bad.write_bytes(b"not a checkpoint")
    with pytest.raises(PolicyFileError, match="not a readable model file"):
        DQNPolicy.load(bad)


def test_shipped_policy_meets_its_bar(h, cfg):
    """The committed policy keeps the robot secure, at least as well as both baselines, and
    earns more reward than both (docs/BENCHMARKS.md has the full test sets)."""
    policy = DQNPolicy.load(DEFAULT_POLICY)
    assert policy.act(np.full(6, 0.5)) in ACTIONS
    results = {name: summarise(run_episodes(p, h, cfg.env, 32, seed=11)[0]) for name, p in
               [("dqn", policy), ("random", RandomPolicy(7, 11)),
                ("rule", HomeostaticRule(h))]}
    assert results["dqn"]["rsr"] >= 0.9998
    assert results["dqn"]["rsr"] >= max(results["random"]["rsr"], results["rule"]["rsr"])
    assert results["dqn"]["mean_reward"] > max(results["random"]["mean_reward"],
                                               results["rule"]["mean_reward"])


@pytest.mark.parametrize("start", [[0.76, 0.66, 0.80, 0.26, 0.41, 0.40],   # unavoidable
                                   [0.95, 0.50, 0.95, 0.92, 0.30, 0.60]])  # already insecure
def test_shipped_policy_recovers_from_insecure_states(h, cfg, start):
    """From drives it cannot (or could not) keep below 0.9, the policy brings them back."""
    policy = DQNPolicy.load(DEFAULT_POLICY)
    env = VecHomeostasisEnv(h, short_env(cfg, 5000), 4, seed=7)
    env.drives[:] = start
    env.act(np.arange(4), policy(env.observe()))
    while env.t[0] < 4000:
        d = env.advance()
        env.act(d.idx, policy(d.decide_obs))
    assert h.secure(env.drives).all()


def test_eval_cli_json(tmp_path, capsys):
    code = main(["eval", "policy", "--episodes", "2", "--seed", "1", "--json",
                 "--out", str(tmp_path)])
    assert code == 0
    out = json.loads(capsys.readouterr().out)
    assert set(out) == {"dqn", "random", "homeostatic_rule"}
    assert set(out["dqn"]["action_histogram"]) == set(ACTIONS)
    for name in ("motivations", "actions", "mood", "training_reward", "training_rsr"):
        assert (tmp_path / "plots" / f"{name}.png").stat().st_size > 1000


def test_eval_cli_tests_the_demonstrating_rule_on_request(tmp_path, capsys):
    train_config = DEFAULT_POLICY.parent / "policy_train.yaml"
    code = main(["eval", "policy", "--episodes", "2", "--seed", "1", "--json", "--demonstrator",
                 "--config", str(train_config), "--out", str(tmp_path)])
    assert code == 0
    out = json.loads(capsys.readouterr().out)
    assert set(out) == {"dqn", "random", "homeostatic_rule", "demonstrator"}
    # serving some motivations early, it chooses differently from the classic rule
    assert out["demonstrator"]["action_histogram"] != out["homeostatic_rule"]["action_histogram"]
    for name in ("random", "homeostatic_rule", "demonstrator"):
        gain = out[name]["dqn_reward_gain"]
        assert gain["mean"] == pytest.approx(out["dqn"]["mean_reward"] - out[name]["mean_reward"])
        assert gain["stderr"] > 0
    assert "dqn_reward_gain" not in out["dqn"]


def test_margin_loss_by_hand():
    q = torch.tensor([[1.0, 2.0, 0.0], [3.0, 1.0, 0.5]])
    expert = torch.tensor([0, 0])
    # row 1: max(1, 2 + 0.8, 0 + 0.8) - 1 = 1.8; row 2: the expert leads by more than 0.8: 0
    assert margin_loss(q, expert, 0.8).item() == pytest.approx(0.9)


@pytest.mark.parametrize("anticipation", [{}, {"achievement": 0.02, "asking": 0.03}])
def test_demonstrations_are_the_rules_choices(h, cfg, anticipation):
    tc = cfg.train.model_copy(update={"num_envs": 8, "demo_transitions": 500,
                                      "demo_anticipation": anticipation})
    demos = collect_demonstrations(h, cfg.env, tc, lambda d: d.reward, DISCOUNTS)
    assert demos.size == 500
    np.testing.assert_array_equal(demos.action, HomeostaticRule(h, anticipation)(demos.obs))
    assert len(set(demos.action.tolist())) >= 4  # the rule acts, it does not only stand by


def test_input_scaling_is_an_affine_map_of_the_motivations():
    scaled = DuelingQNetwork(6, 7, [16], 8, input_offset=0.6, input_scale=0.05)
    plain = DuelingQNetwork(6, 7, [16], 8)
    plain.load_state_dict(scaled.state_dict())
    obs = torch.rand(4, 6)
    torch.testing.assert_close(scaled(obs), plain((obs - 0.6) / 0.05))


@pytest.mark.parametrize(("yaml_text", "message"), [
    ("env: {initial_drives: [0.8, 0.2]}", r"env: .*initial_drives: lower bound 0.8 exceeds"),
    ("train: {demo_initial_drives: [0.0, 1.5]}", r"train\.demo_initial_drives\[1\]: .*less than"),
    ("train: {demo_anticipation: {hunger: 0.02}}", r"train\.demo_anticipation\.hunger"),
    ("train: {demo_anticipation: {asking: -0.1}}", r"train\.demo_anticipation\.asking: .*greater"),
])
def test_bad_ranges_and_anticipations_are_rejected_by_name(tmp_path, yaml_text, message):
    path = tmp_path / "bad.yaml"
    path.write_text(yaml_text)
    with pytest.raises(ConfigError, match=message):
        load_policy_config(path)


def test_only_the_action_that_crosses_the_threshold_counts_as_becoming_insecure(h, cfg):
    env_cfg = short_env(cfg).model_copy(update={"terminate_on_insecure": False})
    env = VecHomeostasisEnv(h, env_cfg, 2, seed=0)
    env.drives[0] = [0.1, 0.1, 0.895, 0.1, 0.1, 0.1]  # belonging crosses 0.9 in 10 steps
    env.drives[1] = [0.1, 0.1, 0.95, 0.1, 0.1, 0.1]   # already insecure
    env.act(np.arange(2), np.array([STAND_BY, STAND_BY]))
    d = env.advance()
    np.testing.assert_array_equal(d.became_insecure, [True, False])
    assert not d.terminal.any()  # these episodes go on


def test_demonstrations_can_go_on_past_insecurity(h, cfg):
    env_cfg = short_env(cfg, 3000).model_copy(update={"terminate_on_insecure": True})
    tc = cfg.train.model_copy(update={"num_envs": 16, "demo_transitions": 3000})
    plain = collect_demonstrations(h, env_cfg, tc, lambda d: d.reward, DISCOUNTS)
    tc = tc.model_copy(update={"demo_past_insecure": True, "demo_initial_drives": (0.0, 1.0)})
    demos = collect_demonstrations(h, env_cfg, tc, lambda d: d.reward, DISCOUNTS)
    assert not (~h.secure(plain.obs)).any()
    assert (~h.secure(demos.obs)).mean() > 0.005  # the rule is shown recovering from 0.9
    np.testing.assert_array_equal(demos.action, HomeostaticRule(h)(demos.obs))
    assert 0 < demos.terminal.sum() < len(demos.terminal)  # crossing 0.9 ends the learning


def test_pretraining_on_demonstrations_imitates_the_rule(h, cfg, tmp_path):
    tiny = cfg.model_copy(update={
        "network": cfg.network.model_copy(update={
            "hidden": [64, 64], "head": 32, "input_offset": 0.6, "input_scale": 0.05}),
        "train": cfg.train.model_copy(update={
            "num_envs": 32, "total_transitions": 1, "learning_rate": 1e-3, "batch_size": 128,
            "target_sync_updates": 200, "checkpoint_every": 5000, "eval_every": 5000,
            "demo_transitions": 6000, "demo_pretrain_updates": 3000, "demo_weight": 10.0})})
    train(h.personality, tiny, tmp_path, progress=False)
    blob = torch.load(tmp_path / "checkpoint.pt", weights_only=True)
    q = DuelingQNetwork(6, 7, **tiny.network.model_dump())
    q.load_state_dict(blob["q"])
    fresh = collect_demonstrations(h, cfg.env, tiny.train.model_copy(
        update={"demo_seed": 7, "demo_transitions": 3000}), lambda d: d.reward, DISCOUNTS)
    with torch.no_grad():
        agree = (q(torch.as_tensor(fresh.obs)).argmax(1).numpy() == fresh.action).mean()
    share_stand_by = (fresh.action == STAND_BY).mean()
    assert agree >= 0.95 > share_stand_by
