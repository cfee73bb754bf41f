"""Training the visual question generator (thesis §3.4.2, §4.3), one phase after another.

1. ``image``: E_I (CNN + projection) and a linear head learn to predict which words occur in
   an image's questions and/or which grounded frames its scene graph holds (multi-label
   cross-entropy, ``train.image_targets``). It stands in for the ImageNet pre-training of the
   thesis's VGG16; afterwards the head is dropped, the CNN trunk is frozen (as VGG16 is in
   the thesis) and its features are computed once per image.
2. ``vae``: eq. 3.16 alone, the reconstruction loss plus the KL divergence to the prior
   (weight warmed up linearly over ``kl_warmup_steps``), training E_I's projection, the
   embedding, E_z and G.
3. ``adversarial``: L_1 = L_rec + L_G1 + L_G2 for the same parameters, and every
   ``generator_steps_per_disc`` steps L_2 = L_D1 + L_D2 for D1 and D2 (eqs. 3.17-3.18).

The Gumbel temperature anneals over the last two phases. Every ``eval_every`` steps of
phases 2 and 3 the model is validated with the programmatic metrics
(:mod:`perception.vqg.training.evaluate`) and the best one is exported to ``vqg.pt``.
Checkpoints, CSV logs and resume come from :class:`textnets.loop.Run`.
"""

from __future__ import annotations

import json
from collections import Counter
from dataclasses import dataclass
from pathlib import Path

import torch
import torch.nn.functional as F  # noqa: N812

from core.checkpoint import atomic_torch_save, read_weights
from core.interrupts import stop_requests, stops_first
from perception.vqg.config import VqgConfig
from perception.vqg.generator import VqgModelError
from perception.vqg.model import (
    VqgModel,
    adversarial_losses,
    discriminator_losses,
    vae_losses,
)
from perception.vqg.questions import frame_key
from perception.vqg.scene import load_scene
from perception.vqg.training.dataset import SplitData, build_vocab, load_split
from perception.vqg.training.evaluate import Selector, load_items
from perception.vqg.training.facts import facts
from perception.vqg.verify import verifier_from_pretraining
from textnets.batch import Batch, BatchSampler
from textnets.functional import temperature
from textnets.loop import Run
from textnets.vocab import Vocab

PHASES = ("image", "vae", "adversarial")
IMAGE_FILE = "image_encoder.pt"  # E_I after pre-training, reusable by other runs
VERIFIER_FILE = "vqg_verifier.pt"  # E_I and its fact columns (perception/vqg/verify.py)


@dataclass
class Data:
    """The training and validation splits, the vocabulary and the question pairs."""

    train: SplitData
    val: SplitData
    vocab: Vocab
    seqs: list[list[int]]
    owner: list[int]
    feats: dict[str, torch.Tensor]
    image_targets: dict[str, torch.Tensor]  # split -> E_I's pre-training targets (N, T)
    target_names: list[str]                  # what each of the T columns stands for

    def trunk_features(self, model: VqgModel, split: str) -> torch.Tensor:
        """The frozen CNN trunk's features of one split (computed once)."""
        if split not in self.feats:
            model.eval()
            images = getattr(self, split).images
            with torch.no_grad():
                self.feats[split] = torch.cat([model.image.features(images[i:i + 64])
                                               for i in range(0, len(images), 64)])
        return self.feats[split]


def prepare_data(cfg: VqgConfig, out_dir: Path) -> Data:
    """Load both splits (images through the run folder's cache) and the vocabulary."""
    d = cfg.data
    root = d.resolved_dir()
    train = load_split(root, "train", d.image_width, d.image_height, out_dir / "cache")
    val = load_split(root, "val", d.image_width, d.image_height, out_dir / "cache")
    vocab = build_vocab(train, d.min_count)
    seqs, owner = train.pairs(vocab, d.max_words)
    targets, names = pretraining_targets(cfg, root, {"train": train, "val": val}, vocab)
    return Data(train, val, vocab, seqs, owner, {}, targets, names)


def _multi_hot(rows: list[set[int]], width: int) -> torch.Tensor:
    out = torch.zeros(len(rows), width)
    for i, cols in enumerate(rows):
        out[i, sorted(cols)] = 1.0
    return out


def pretraining_targets(cfg: VqgConfig, root: Path, splits: dict[str, SplitData],
                        vocab: Vocab) -> tuple[dict[str, torch.Tensor], list[str]]:
    """Multi-hot targets of E_I's pre-training per split and the names of their columns,
    side by side for each source of ``train.image_targets``: ``words`` (``word:W``), the
    vocabulary words of the image's questions; ``facts`` (``fact:KEY``), the grounded
    frames of its scene graph (:func:`perception.vqg.training.facts.facts`: which objects, colours,
    counts, places and relations are true together) that hold in at least
    ``image_fact_min_images`` training images and fail in as many."""
    tc = cfg.train
    parts: dict[str, list[torch.Tensor]] = {s: [] for s in splits}
    names: list[str] = []
    if "words" in tc.image_targets:
        names += [f"word:{w}" for w in vocab.itos]
        for s, split in splits.items():
            rows = [{w for q in qs for w in vocab.encode(q)} for qs in split.questions]
            parts[s].append(_multi_hot(rows, len(vocab)))
    if "facts" in tc.image_targets:
        keys = {s: [{repr(frame_key(f)) for f in facts(
                    load_scene(root / "scenes" / s / f"{i}.json"))} for i in split.ids]
                for s, split in splits.items()}
        n, least = len(keys["train"]), tc.image_fact_min_images
        counts = Counter(k for row in keys["train"] for k in row)
        index = {k: j for j, k in enumerate(sorted(
            k for k, c in counts.items() if least <= c <= n - least))}
        names += [f"fact:{k}" for k in index]
        for s, rows in keys.items():
            parts[s].append(_multi_hot([{index[k] for k in row if k in index} for row in rows],
                                       len(index)))
    return {s: torch.cat(p, dim=1) for s, p in parts.items()}, names


def train(cfg: VqgConfig, out_dir: Path, resume: bool = False, progress: bool = True,
          image_from: Path | None = None) -> dict:
    """Run (or continue) every phase into ``out_dir``; returns the summary it also writes.

    ``image_from`` (another run's ``image_encoder.pt``, same data) replaces the ``image``
    phase: the ablations share one pre-trained E_I.
    """
    out_dir.mkdir(parents=True, exist_ok=True)
    tc = cfg.train
    torch.set_num_threads(tc.threads)
    torch.manual_seed(tc.seed)
    data = prepare_data(cfg, out_dir)
    model = VqgModel(len(data.vocab), cfg.model)
    head = torch.nn.Linear(cfg.model.feature_dim, data.image_targets["train"].shape[1])
    run = Run(cfg, out_dir, {"vqg": model, "image_head": head}, resume, progress, name="vqg")
    run.folder.use_config(cfg)
    summary_path = out_dir / "summary.json"
    summary = json.loads(summary_path.read_text()) if summary_path.exists() else {}
    summary.update({"vocab": len(data.vocab), "questions": len(data.seqs),
                    "images": {"train": len(data.train.ids), "val": len(data.val.ids)}})
    selector = Selector(run, model, data.vocab, load_items(cfg, "val", tc.select_images))
    if image_from is not None and "image" not in run.done:
        summary["image"] = reuse_image_encoder(model, data.vocab, image_from)
        run.finish("image")
    with stop_requests():  # SIGINT or SIGTERM: a checkpoint before the next step, then stop
        for phase in PHASES:
            if phase in run.done:
                continue
            summary.update(PHASE_FNS[phase](run, data, model, selector) or {})
            summary.setdefault("wall_s_after", {})[phase] = round(run.wall(), 1)
            run.finish(phase)
            summary_path.write_text(json.dumps(summary, indent=2))
    summary["selected"] = selector.best_meta()
    summary_path.write_text(json.dumps(summary, indent=2))
    return summary


def _step(opt: torch.optim.Optimizer, loss: torch.Tensor, clip: float) -> None:
    opt.zero_grad()
    loss.backward()
    torch.nn.utils.clip_grad_norm_([p for g in opt.param_groups for p in g["params"]], clip)
    opt.step()


def _adam(run: Run, params: list, lr: float) -> torch.optim.Optimizer:
    return torch.optim.Adam(params, lr=lr, betas=run.cfg.train.betas)


def phase_image(run: Run, data: Data, model: VqgModel, _: Selector) -> dict:
    """Pre-train E_I with the run's ``image_head`` on the multi-label targets of each
    training image."""
    tc, n, head = run.cfg.train, len(data.train.ids), run.nets["image_head"]
    targets = data.image_targets["train"]
    sampler = BatchSampler([[i] for i in range(n)], list(range(n)), tc.image_batch, tc.seed + 1)
    opt = torch.optim.Adam([*model.image.parameters(), *head.parameters()], lr=tc.image_lr,
                           weight_decay=tc.weight_decay)

    def bce(images: torch.Tensor, target: torch.Tensor) -> torch.Tensor:
        logits = head(model.image(model.image.features(images)))
        return F.binary_cross_entropy_with_logits(logits, target)

    @stops_first
    def step(_: int) -> dict[str, float]:
        model.train()
        idx = sampler.next().labels
        loss = bce(data.train.images[idx], targets[idx])
        _step(opt, loss, tc.grad_clip)
        return {"bce": loss.item()}

    run.loop("image", tc.image_steps, step, ["bce"], {"opt": opt}, {"train": sampler})
    model.eval()
    with torch.no_grad():
        val = round(bce(data.val.images, data.image_targets["val"]).item(), 4)
    atomic_torch_save({"vocab": list(data.vocab.itos), "state_dict": model.image.state_dict(),
                       "val_bce": val}, run.out_dir / IMAGE_FILE)
    if any(n.startswith("fact:") for n in data.target_names):
        d = run.cfg.data
        verifier = verifier_from_pretraining(model.image, head, data.target_names,
                                             run.cfg.model, (d.image_width, d.image_height))
        verifier.save(run.out_dir / VERIFIER_FILE, {"val_bce": val})
    return {"image": {"val_bce": val}}


def reuse_image_encoder(model: VqgModel, vocab: Vocab, path: Path) -> dict:
    """Load a pre-trained E_I written by :func:`phase_image` (same vocabulary required)."""
    blob = read_weights(path, VqgModelError, "train a full run first")
    try:
        if blob["vocab"] != list(vocab.itos):
            raise ValueError("its vocabulary differs from this data set's")
        model.image.load_state_dict(blob["state_dict"])
    except (KeyError, TypeError, ValueError, RuntimeError) as exc:
        raise VqgModelError(f"{path}: cannot reuse this image encoder ({exc})") from None
    return {"from": str(path), "val_bce": blob["val_bce"]}


def _per_word(batch: Batch) -> float:
    return float(batch.mask.sum()) / len(batch.lengths)


def phase_vae(run: Run, data: Data, model: VqgModel, selector: Selector) -> None:
    """Eq. 3.16: reconstruction + KL (warmed up) with the Gumbel temperature annealed."""
    tc = run.cfg.train
    feats = data.trunk_features(model, "train")
    sampler = BatchSampler(data.seqs, data.owner, tc.batch_size, tc.seed + 2)
    opt = _adam(run, model.generator_parameters(), tc.lr)

    @stops_first
    def step(i: int) -> dict[str, float]:
        model.train()
        batch = sampler.next()
        tau = temperature(i, tc.gumbel.tau_start, tc.gumbel.decay, tc.gumbel.every,
                          tc.gumbel.tau_min)
        kl_weight = tc.weights.kl * min(1.0, (i + 1) / max(1, tc.kl_warmup_steps))
        out = vae_losses(model, batch, feats[batch.labels], tau, tc.kl_free_nats)
        _step(opt, tc.weights.rec * out.rec + kl_weight * out.kl_loss, tc.grad_clip)
        return {"rec": out.rec.item() / _per_word(batch), "kl": out.kl.item(), "tau": tau}

    run.loop("vae", tc.vae_steps, step, ["rec", "kl", "tau"], {"opt": opt},
             {"train": sampler}, on_eval=lambda at: selector("vae", at),
             eval_every=tc.eval_every)
    if tc.vae_steps % tc.eval_every:
        selector("vae", tc.vae_steps)


def phase_adversarial(run: Run, data: Data, model: VqgModel, selector: Selector) -> None:
    """Eqs. 3.16-3.18: G, E_z and E_I against D1 (professor forcing) and D2 (image match)."""
    tc, w = run.cfg.train, run.cfg.train.weights
    feats = data.trunk_features(model, "train")
    sampler = BatchSampler(data.seqs, data.owner, tc.batch_size, tc.seed + 3)
    g_opt = _adam(run, model.generator_parameters(), tc.adv_lr)
    optimizers = {"g": g_opt}
    if model.d1 is not None or model.d2 is not None:
        optimizers["d"] = _adam(run, model.discriminator_parameters(), tc.disc_lr)

    @stops_first
    def step(i: int) -> dict[str, float]:
        model.train()
        batch = sampler.next()
        tau = temperature(tc.vae_steps + i, tc.gumbel.tau_start, tc.gumbel.decay,
                          tc.gumbel.every, tc.gumbel.tau_min)
        out = vae_losses(model, batch, feats[batch.labels], tau, tc.kl_free_nats)
        fake, g = adversarial_losses(model, out, tau)
        total = w.rec * out.rec + w.kl * out.kl_loss + sum(getattr(w, k) * v for k, v in g.items())
        _step(g_opt, total, tc.grad_clip)
        logged = {"rec": out.rec.item() / _per_word(batch), "kl": out.kl.item(), "tau": tau,
                  **{k: v.item() for k, v in g.items()}}
        if "d" in optimizers and (i + 1) % tc.generator_steps_per_disc == 0:
            d = discriminator_losses(model, out, fake)
            _step(optimizers["d"], sum(getattr(w, k) * v for k, v in d.items()), tc.grad_clip)
            logged |= {k: v.item() for k, v in d.items()}
        return logged

    fields = ["rec", "kl", "g1", "g2", "d1", "d2", "d2_mismatch", "tau"]
    run.loop("adversarial", tc.adversarial_steps, step, fields, optimizers,
             {"train": sampler}, on_eval=lambda at: selector("adversarial", at),
             eval_every=tc.eval_every)
    if tc.adversarial_steps % tc.eval_every:
        selector("adversarial", tc.adversarial_steps)


PHASE_FNS = {"image": phase_image, "vae": phase_vae, "adversarial": phase_adversarial}
