"""Dueling Double DQN training on the abstract household (thesis §3.2.6, Algorithm 4).

One readable loop in the CleanRL manner: every hyper-parameter comes from the ``train``
section of the policy YAML. Progress is written as it goes (flushed CSV logs, atomic
resumable checkpoints), so an interrupted run continues with ``--resume``. Every
``eval_every`` updates the greedy policy plays validation episodes; the best one so far is
exported as ``policy.pt``.
"""

from __future__ import annotations

import copy
import csv
import itertools
import json
from pathlib import Path

import numpy as np
import torch
import torch.nn.functional as F  # noqa: N812
from tqdm import tqdm

from core.checkpoint import TrainingFolder, atomic_torch_save
from core.config_files import StrictModel
from core.interrupts import stop_point, stop_requests
from mind.homeostasis import Homeostasis
from mind.personality import ACTIONS, MOTIVATIONS, Personality
from mind.policy.agent import DQNPolicy, PolicyFileError
from mind.policy.config import PolicyConfig, TrainConfig
from mind.policy.network import DuelingQNetwork
from mind.policy.training.demo import collect_demonstrations, margin_loss
from mind.policy.training.env import Decisions, VecHomeostasisEnv
from mind.policy.training.evaluate import run_episodes, summarise
from mind.policy.training.replay import NStepWriter, ReplayBuffer

LOG_FIELDS = ["transitions", "updates", "episode", "return", "rsr", "epsilon", "wall_s"]
EVAL_FIELDS = ["transitions", "updates", "rsr", "mean_reward", "best", "wall_s"]


def linear_schedule(start: float, end: float, duration: float, t: float) -> float:
    """Linear decay from ``start`` to ``end`` over ``duration``, then constant."""
    return end + (start - end) * max(0.0, 1.0 - t / duration)


def export_policy(q: DuelingQNetwork, cfg: PolicyConfig, path: Path, meta: dict) -> None:
    """Write the greedy policy's weights (loadable with ``weights_only=True``)."""
    atomic_torch_save({"network": cfg.network.model_dump(), "state_dict": q.state_dict(),
                       "meta": meta}, path)


def action_discounts(gamma: float, durations: np.ndarray, gamma_steps: int | None
                     ) -> np.ndarray:
    """The discount of each action's transition: ``gamma`` per decision, or with
    ``gamma_steps`` ``gamma ** (duration / gamma_steps)``, so that a long action (a charge
    of 1000 steps) costs the future as much time as it takes (semi-Markov discounting)."""
    exponent = np.ones(len(durations)) if gamma_steps is None else durations / gamma_steps
    return (gamma ** exponent).astype(np.float32)


def training_reward(d: Decisions, durations: np.ndarray, tc: TrainConfig) -> np.ndarray:
    """The reward a transition is stored with: eq. 3.7's, plus ``insecure_penalty`` where
    the robot became insecure during the action, minus ``time_cost``
    per step the action took (an average-reward baseline: over a fixed stretch of time it
    subtracts the same total from every policy, but a per-decision learner then sees what a
    long action costs)."""
    return (d.reward + tc.insecure_penalty * d.became_insecure
            - tc.time_cost * durations[d.action])


def dqn_update(q: DuelingQNetwork, target: DuelingQNetwork, optimizer: torch.optim.Optimizer,
               batch: tuple[np.ndarray, ...], max_grad_norm: float | None, n_demo: int = 0,
               demo_weight: float = 0.0, demo_margin: float = 0.0) -> float:
    """One gradient step on (y - Q(s, a))^2 with the Double-DQN target y, bootstrapped with
    each transition's stored discount (one action's, or n actions' for an n-step return;
    :class:`~mind.policy.training.replay.NStepWriter`). The last ``n_demo``
    transitions of ``batch`` are demonstrations: they add ``demo_weight`` times
    :func:`~mind.policy.training.demo.margin_loss`."""
    obs, act, rew, nxt, gamma, terminal = (torch.as_tensor(x) for x in batch)
    q_both = q(torch.cat([obs, nxt]))  # one pass of the online net for s and s'
    q_obs, q_next = q_both[: len(obs)], q_both[len(obs):].detach()
    with torch.no_grad():  # the online net picks the next action, the target net rates it
        best = q_next.argmax(dim=1, keepdim=True)
        y = rew + gamma * (1.0 - terminal) * target(nxt).gather(1, best).squeeze(1)
    loss = F.mse_loss(q_obs.gather(1, act[:, None]).squeeze(1), y)
    if n_demo:
        loss = loss + demo_weight * margin_loss(q_obs[-n_demo:], act[-n_demo:], demo_margin)
    optimizer.zero_grad()
    loss.backward()
    if max_grad_norm is not None:
        torch.nn.utils.clip_grad_norm_(q.parameters(), max_grad_norm)
    optimizer.step()
    return loss.item()


def sample_batch(memory: ReplayBuffer, demos: ReplayBuffer | None, rng: np.random.Generator,
                 tc: TrainConfig, pretraining: bool) -> tuple[tuple[np.ndarray, ...], int]:
    """A mini-batch and how many of its (last) transitions are demonstrations: all of them
    while pre-training, ``demo_share`` of them later, none without demonstrations."""
    if demos is None:
        return memory.sample(rng, tc.batch_size), 0
    n_demo = tc.batch_size if pretraining else round(tc.batch_size * tc.demo_share)
    parts = [memory.sample(rng, tc.batch_size - n_demo)] if n_demo < tc.batch_size else []
    parts.append(demos.sample(rng, n_demo))
    return tuple(np.concatenate(x) for x in zip(*parts, strict=True)), n_demo


def validate(q: DuelingQNetwork, homeostasis: Homeostasis, cfg: PolicyConfig) -> dict:
    """Greedy performance on the validation episodes (seeds apart from the test seeds)."""
    policy = DQNPolicy(copy.deepcopy(q))
    episodes, _ = run_episodes(policy, homeostasis, cfg.env, cfg.train.eval_episodes,
                               cfg.train.eval_seed)
    return summarise(episodes)


def selection_score(stats: dict, rsr_target: float) -> tuple[float, float]:
    """Policies are ranked by secure rate up to the target, then by reward."""
    return (min(stats["rsr"], rsr_target), stats["mean_reward"])


class PolicyRunConfig(StrictModel):
    """What a policy training's ``resolved_config.yaml`` holds."""

    personality: Personality
    policy: PolicyConfig


def train(personality: Personality, cfg: PolicyConfig, out_dir: Path, resume: bool = False,
          progress: bool = True) -> dict:
    """Train a policy into ``out_dir``; returns a summary with the exported policy path.

    SIGINT and SIGTERM stop it at the next decision round (or pre-training update) with a
    checkpoint written there (:mod:`core.interrupts`); ``resume`` continues exactly."""
    tc = cfg.train
    folder = TrainingFolder(out_dir, resume, PolicyFileError)
    folder.use_config(PolicyRunConfig(personality=personality, policy=cfg))
    eval_path = out_dir / "eval_log.csv"
    torch.set_num_threads(1)
    torch.manual_seed(tc.seed)
    rng = np.random.default_rng(tc.seed)

    homeostasis = Homeostasis(personality)
    env_cfg = cfg.env.model_copy(update={"episode_steps": tc.episode_steps,
                                         "terminate_on_insecure": tc.terminate_on_insecure})
    env = VecHomeostasisEnv(homeostasis, env_cfg, tc.num_envs, seed=tc.seed)
    n_obs, n_act = len(MOTIVATIONS), len(ACTIONS)
    q = DuelingQNetwork(n_obs, n_act, **cfg.network.model_dump())
    target = copy.deepcopy(q)
    optimizer = torch.optim.RMSprop(q.parameters(), lr=tc.learning_rate,
                                    alpha=tc.rmsprop_alpha, eps=tc.rmsprop_eps,
                                    foreach=True)
    memory = ReplayBuffer(tc.buffer_size, n_obs)
    discounts = action_discounts(tc.gamma, homeostasis.duration, tc.gamma_steps)
    demos = None if tc.demo_transitions == 0 else collect_demonstrations(
        homeostasis, env_cfg, tc, lambda d: training_reward(d, homeostasis.duration, tc),
        discounts)
    writer = NStepWriter(memory, tc.n_step, tc.num_envs, n_obs, discounts)
    transitions = updates = episodes = evals = 0
    credit, finished = 0.0, False
    best: tuple[float, float] | None = None

    if folder.state is not None:
        state = folder.state
        folder.restore(q=q, target=target, optimizer=optimizer, memory=memory, env=env)
        rng.bit_generator.state = state["rng"]
        torch.set_rng_state(state["torch_rng"])
        transitions, updates, episodes = state["counters"]
        credit, best, evals = state["credit"], state["best"], state["evals"]
        finished = state["finished"]
    # on resume, the logs keep their rows up to the checkpoint
    validated = itertools.count()
    folder.open_log(eval_path.name, EVAL_FIELDS, keep=lambda _: next(validated) < evals).close()
    log_file = folder.open_log("train_log.csv", LOG_FIELDS, keep=lambda r: int(r[2]) <= episodes)
    log = csv.writer(log_file)

    def save_checkpoint() -> None:
        folder.save({
            "q": q.state_dict(), "target": target.state_dict(),
            "optimizer": optimizer.state_dict(), "memory": memory.state_dict(),
            "env": env.state_dict(), "rng": rng.bit_generator.state,
            "torch_rng": torch.get_rng_state(),
            "counters": (transitions, updates, episodes), "credit": credit, "best": best,
            "evals": evals, "finished": finished,
        })

    def validate_and_keep_best() -> None:
        """Validate the greedy policy; export it when it beats the best so far."""
        nonlocal best, evals
        stats = validate(q, homeostasis, cfg)
        score = selection_score(stats, tc.select_rsr)
        improved = best is None or score > best
        wall = folder.wall()
        if improved:
            best = score
            export_policy(q, cfg, out_dir / "policy.pt",
                          {"transitions": transitions, "updates": updates, "seed": tc.seed,
                           "validation_rsr": stats["rsr"],
                           "validation_reward": stats["mean_reward"]})
        with eval_path.open("a", newline="") as fh:
            csv.writer(fh).writerow([transitions, updates, f"{stats['rsr']:.6f}",
                                     f"{stats['mean_reward']:.2f}", int(improved),
                                     f"{wall:.1f}"])
        evals += 1

    def choose(obs: np.ndarray) -> np.ndarray:
        eps = linear_schedule(tc.epsilon_start, tc.epsilon_end,
                              tc.exploration_fraction * tc.total_transitions, transitions)
        with torch.no_grad():
            greedy = q(torch.as_tensor(obs, dtype=torch.float32)).argmax(-1).numpy()
        explore = rng.random(len(obs)) < eps
        return np.where(explore, rng.integers(0, n_act, len(obs)), greedy)

    def update(pretraining: bool) -> None:
        """One gradient step, then the target sync, validation and checkpoint when due."""
        nonlocal updates
        if tc.learning_rate_end is not None:
            for group in optimizer.param_groups:
                group["lr"] = linear_schedule(tc.learning_rate, tc.learning_rate_end,
                                              tc.total_transitions, transitions)
        batch, n_demo = sample_batch(memory, demos, rng, tc, pretraining)
        dqn_update(q, target, optimizer, batch, tc.max_grad_norm, n_demo,
                   tc.demo_weight if pretraining or tc.demo_weight_rl is None
                   else tc.demo_weight_rl, tc.demo_margin)
        updates += 1
        if updates % tc.target_sync_updates == 0:
            target.load_state_dict(q.state_dict())
        if updates % tc.eval_every == 0:
            validate_and_keep_best()
        if updates % tc.checkpoint_every == 0:
            save_checkpoint()

    def learn() -> None:
        """The gradient steps the collected decisions have earned."""
        nonlocal credit
        while credit >= 1.0:
            credit -= 1.0
            update(pretraining=False)

    recent: list[dict] = []
    with stop_requests(), log_file:
        for _ in tqdm(range(updates, tc.demo_pretrain_updates if demos is not None else 0),
                      disable=not progress, desc="pre-train on the rule", unit="upd"):
            stop_point(save_checkpoint)
            update(pretraining=True)
        waiting = np.flatnonzero(env.remaining <= 0)  # a fresh run's envs, all of them
        if len(waiting):
            env.act(waiting, choose(env.observe(waiting)))
        learn()  # a checkpoint written between two updates left some to do
        with tqdm(total=tc.total_transitions, initial=transitions, disable=not progress,
                  desc="train policy", unit="dec") as bar:
            while transitions < tc.total_transitions:
                stop_point(save_checkpoint)
                d = env.advance()
                writer.add(d, training_reward(d, homeostasis.duration, tc), d.terminal)
                transitions += len(d.idx)
                bar.update(len(d.idx))
                env.act(d.idx, choose(d.decide_obs))
                eps = linear_schedule(tc.epsilon_start, tc.epsilon_end,
                                      tc.exploration_fraction * tc.total_transitions, transitions)
                for ep in d.episodes:
                    episodes += 1
                    log.writerow([transitions, updates, episodes, f"{ep['return']:.3f}",
                                  f"{ep['rsr']:.6f}", f"{eps:.4f}",
                                  f"{folder.wall():.1f}"])
                    recent = [*recent, ep][-tc.num_envs:]
                if d.episodes:
                    log_file.flush()
                    bar.set_postfix(eps=f"{eps:.2f}",
                                    rsr=f"{np.mean([e['rsr'] for e in recent]):.4f}",
                                    ret=f"{np.mean([e['return'] for e in recent]):.0f}")
                if memory.size >= tc.learning_starts:
                    credit += len(d.idx) * tc.updates_per_transition
                    learn()
        if not finished:  # a finished run resumed has nothing left to do
            validate_and_keep_best()
            finished = True
            save_checkpoint()
    wall = folder.wall()
    summary = {"transitions": transitions, "updates": updates, "episodes": episodes,
               "wall_s": round(wall, 1), "seed": tc.seed,
               "best_validation": {"rsr": best[0], "mean_reward": best[1]}}
    (out_dir / "summary.json").write_text(json.dumps(summary, indent=2))
    return summary
