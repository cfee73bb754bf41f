"""Training the style-transfer system (thesis §3.3, §4.2), one readable phase after another.

1. ``classifier``: the TextCNN sentiment judge on the training split -> ``classifier.pt``.
2. ``lm``: the LSTM language model for fluency -> ``lm.pt``.
3. ``pretrain``: E_y auto-encoder, E_z and G as style-conditioned language models
   (eqs. 3.8-3.10).
4. ``reconstruct``: E_y + reconstruction (eqs. 3.8, 3.11), a short warm-up.
5. ``adversarial``: L_1 = L_S + L_rec + L_G + 0.3 L_cycle for G, E_z, E_y, with
   ``generator_steps_per_disc`` generator steps per discriminator step (eq. 3.13);
   every ``eval_every`` steps the greedy transfer of validation sentences is scored (transfer
   accuracy by the classifier, self-BLEU) and the best model so far is exported to
   ``style.pt``.

Every hyper-parameter comes from the YAML config; see :mod:`textnets.loop` for the
checkpoint, logs and resume.
"""

from __future__ import annotations

import csv
import json
import math
from dataclasses import dataclass, field
from pathlib import Path

import torch

from core.checkpoint import atomic_copy
from core.interrupts import stop_requests, stops_first
from dialogue.style.config import CLASSIFIER_FILE, LM_FILE, STYLE_FILE, StyleConfig
from dialogue.style.decode import transfer_ids
from dialogue.style.files import StyleModelError, load_classifier, load_lm, save_model
from dialogue.style.model import StyleTransferModel
from dialogue.style.nets import LanguageModel, SentimentClassifier
from dialogue.style.training.data import Split, load_splits, style_markers
from dialogue.style.training.finetune import conversation_set, start_from
from dialogue.style.training.losses import discriminator_loss, pretrain_losses, transfer_losses
from dialogue.style.training.metrics import accuracy, perplexity, self_bleu
from textnets.batch import BatchSampler
from textnets.functional import temperature
from textnets.loop import Run
from textnets.vocab import Vocab

PHASES = ("classifier", "lm", "pretrain", "reconstruct", "adversarial")
PER_SENTENCE = {"lm_enc", "lm_gen", "rec", "cycle"}  # logged per word
VALID_FIELDS = ["step", "accuracy", "self_bleu", "score", "best", "wall_s"]


@dataclass
class Data:
    """The re-split corpus, its vocabulary and the id sequences of every split."""

    splits: dict[str, Split]
    vocab: Vocab
    ids: dict[str, list[list[int]]]
    extra_ids: list[list[int]] = field(default_factory=list)   # conversational lines
    extra_labels: list[int] = field(default_factory=list)      # ... as the judge labels them
    fine_tuning: bool = False     # started from a trained model (not a selection candidate)

    def transfer_train(self) -> tuple[list[list[int]], list[int]]:
        """The transfer model's training set: Yelp's training split and the conversational
        lines (the judges train on Yelp alone)."""
        return self.ids["train"] + self.extra_ids, self.splits["train"].labels + self.extra_labels


def prepare_data(cfg: StyleConfig) -> Data:
    """Load and re-split the Yelp files; build the vocabulary on the training split only."""
    splits = load_splits(cfg.data)
    vocab = Vocab.build(splits["train"].sentences, cfg.data.min_count)
    ids = {k: [vocab.encode(s) for s in sp.sentences] for k, sp in splits.items()}
    return Data(splits, vocab, ids)


def balanced_subset(split: Split, n: int) -> tuple[list[list[str]], list[int]]:
    """The first ``n // 2`` sentences of each class (the split is already shuffled)."""
    sents, labels = [], []
    for c in (0, 1):
        chosen = split.of_class(c)[: max(1, n // 2)]
        sents += chosen
        labels += [c] * len(chosen)
    return sents, labels


def score(acc: float, bleu: float, min_bleu: float) -> float:
    """Model selection: past the BLEU floor the accuracy counts, below it sqrt(acc * BLEU).

    Values above 100 mean the floor is met.
    """
    if bleu >= min_bleu:
        return 100.0 + 100.0 * acc
    return math.sqrt(max(acc, 0.0) * 100.0 * max(bleu, 0.0))


def adopt_judges(run: Run, data: Data, nets: dict, judges: Path) -> dict:
    """Take the classifier and language model of an earlier run in ``judges`` instead of
    training them (an ablation is then scored by the very same judges); both must have
    been trained on this data split. Returns their summary entries."""
    summary = {}
    for phase, file, load in (("classifier", CLASSIFIER_FILE, load_classifier),
                              ("lm", LM_FILE, load_lm)):
        net, vocab, blob = load(judges / file)
        if vocab.itos != data.vocab.itos or blob["meta"].get("data") != run.cfg.data.model_dump(
                mode="json"):
            raise StyleModelError(f"{judges / file}: trained on another data split")
        nets[phase].load_state_dict(net.state_dict())
        atomic_copy(judges / file, run.out_dir / file)
        summary[phase] = {k: v for k, v in blob["meta"].items() if k != "data"}
        run.finish(phase)
    return summary


def train(cfg: StyleConfig, out_dir: Path, resume: bool = False, progress: bool = True,
          judges: Path | None = None, init: Path | None = None) -> dict:
    """Run (or continue) every phase into ``out_dir``; returns the summary it also writes.
    ``judges``: a run folder whose classifier and language model are reused; ``init``: a
    ``style.pt`` whose weights the transfer model starts from (fine-tuning)."""
    out_dir.mkdir(parents=True, exist_ok=True)
    tc = cfg.train
    torch.set_num_threads(tc.threads)
    torch.manual_seed(tc.seed)
    data = prepare_data(cfg)
    v = len(data.vocab)
    nets = {"classifier": SentimentClassifier(v, cfg.classifier), "lm": LanguageModel(v, cfg.lm),
            "style": StyleTransferModel(v, cfg.model)}
    if cfg.model.mask_ratio is not None:
        hidden = style_markers(data.splits["train"], data.vocab, cfg.model.mask_ratio,
                               cfg.model.mask_min_count)
        nets["style"].set_masked([data.vocab.stoi[w] for w in hidden])
    if init is not None:
        start_from(nets["style"], data.vocab, init)
        data.fine_tuning = True
    run = Run(cfg, out_dir, nets, resume, progress)
    run.folder.use_config(cfg)
    summary_path = out_dir / "summary.json"
    summary = json.loads(summary_path.read_text()) if summary_path.exists() else {}
    summary.update({"vocab": v, "sentences": {k: len(s.labels) for k, s in data.splits.items()}})
    if judges is not None and run.state is None and not run.done:
        summary.update(adopt_judges(run, data, nets, judges))
    with stop_requests():  # SIGINT or SIGTERM: a checkpoint before the next step, then stop
        for phase in PHASES:
            if phase == "pretrain" and (cfg.conversation.chat or cfg.conversation.qa):
                data.extra_ids, data.extra_labels, counts = conversation_set(
                    cfg, data.vocab, nets["classifier"])
                summary.update(counts)
            if phase in run.done:
                continue
            summary.update(PHASE_FNS[phase](run, data, nets) or {})
            summary.setdefault("wall_s_after", {})[phase] = round(run.wall(), 1)
            run.finish(phase)
            summary_path.write_text(json.dumps(summary, indent=2))
    return summary


def per_word(losses: dict[str, torch.Tensor], batch) -> dict[str, float]:
    """Loggable values: sentence NLLs divided by the mean sentence length (nats per word)."""
    words = float(batch.mask.sum()) / len(batch.labels)
    return {k: v.item() / words if k in PER_SENTENCE else v.item() for k, v in losses.items()}


def _step(net: torch.nn.Module, opt: torch.optim.Optimizer, loss: torch.Tensor,
          clip: float | None = None) -> None:
    opt.zero_grad()
    loss.backward()
    if clip is not None:
        torch.nn.utils.clip_grad_norm_([p for g in opt.param_groups for p in g["params"]], clip)
    opt.step()


def phase_classifier(run: Run, data: Data, nets: dict) -> dict:
    """Train the TextCNN judge; export it with its validation and test accuracy."""
    c, net = run.cfg.classifier, nets["classifier"]
    sampler = BatchSampler(data.ids["train"], data.splits["train"].labels, c.batch_size,
                           run.cfg.train.seed + 1)
    opt = torch.optim.Adam(net.parameters(), lr=c.lr)

    @stops_first
    def step(_: int) -> dict[str, float]:
        net.train()
        batch = sampler.next()
        loss = net.loss(batch)
        _step(net, opt, loss)
        return {"loss": loss.item()}

    total = math.ceil(c.epochs * sampler.batches_per_epoch())
    run.loop("classifier", total, step, ["loss"], {"opt": opt}, {"train": sampler})
    result = {f"{k}_accuracy": accuracy(net, data.vocab, data.splits[k].sentences,
                                        data.splits[k].labels) for k in ("valid", "test")}
    save_model(run.out_dir / CLASSIFIER_FILE, "classifier", data.vocab, c.model_dump(), net,
               {**result, "data": run.cfg.data.model_dump(mode="json")})
    return {"classifier": result}


def phase_lm(run: Run, data: Data, nets: dict) -> dict:
    """Train the fluency language model; export it with its validation perplexity."""
    c, net = run.cfg.lm, nets["lm"]
    sampler = BatchSampler(data.ids["train"], data.splits["train"].labels, c.batch_size,
                           run.cfg.train.seed + 2)
    opt = torch.optim.Adam(net.parameters(), lr=c.lr)

    @stops_first
    def step(_: int) -> dict[str, float]:
        net.train()
        loss = net.loss(sampler.next())
        _step(net, opt, loss, clip=5.0)
        return {"nll": loss.item()}

    total = math.ceil(c.epochs * sampler.batches_per_epoch())
    run.loop("lm", total, step, ["nll"], {"opt": opt}, {"train": sampler})
    result = {"valid_perplexity": perplexity(net, data.vocab, data.splits["valid"].sentences)}
    save_model(run.out_dir / LM_FILE, "lm", data.vocab, c.model_dump(), net,
               {**result, "data": run.cfg.data.model_dump(mode="json")})
    return {"lm": result}


def _style_optimizer(run: Run, params, lr: float) -> torch.optim.Optimizer:
    return torch.optim.Adam(params, lr=lr, betas=run.cfg.train.betas)


def phase_pretrain(run: Run, data: Data, nets: dict) -> None:
    """Eqs. 3.8-3.10: language-model pre-training of E_z and G with the style auto-encoder."""
    tc, model = run.cfg.train, nets["style"]
    sampler = BatchSampler(*data.transfer_train(), tc.batch_size, tc.seed + 3)
    opt = _style_optimizer(run, model.generator_parameters(), tc.pretrain_lr)

    @stops_first
    def step(_: int) -> dict[str, float]:
        model.train()
        batch = sampler.next()
        losses = pretrain_losses(model, batch)
        _step(model, opt, sum(losses.values()), tc.grad_clip)
        return per_word(losses, batch)

    run.loop("pretrain", tc.lm_steps, step, ["style", "lm_enc", "lm_gen"], {"opt": opt},
             {"train": sampler})


def phase_reconstruct(run: Run, data: Data, nets: dict) -> None:
    """Eqs. 3.8 and 3.11: reconstruction warm-up before the adversarial phase."""
    tc, model = run.cfg.train, nets["style"]
    sampler = BatchSampler(*data.transfer_train(), tc.batch_size, tc.seed + 4)
    opt = _style_optimizer(run, model.generator_parameters(), tc.pretrain_lr)

    @stops_first
    def step(_: int) -> dict[str, float]:
        model.train()
        batch = sampler.next()
        total, losses, _ = transfer_losses(model, batch, 1.0, tc.weights, False)
        _step(model, opt, total, tc.grad_clip)
        return per_word(losses, batch)

    run.loop("reconstruct", tc.rec_steps, step, ["style", "rec"], {"opt": opt},
             {"train": sampler})


def phase_adversarial(run: Run, data: Data, nets: dict) -> dict:
    """Cross-alignment with the N+1 discriminator and cycle consistency; exports style.pt."""
    cfg, tc, model = run.cfg, run.cfg.train, nets["style"]
    sampler = BatchSampler(*data.transfer_train(), tc.batch_size, tc.seed + 5)
    g_opt = _style_optimizer(run, model.generator_parameters(), tc.lr)
    d_opt = torch.optim.Adam(model.discriminator.parameters(), lr=tc.disc_lr, betas=tc.betas)
    valid_sents, valid_labels = balanced_subset(data.splits["valid"], tc.eval_sentences)
    valid_ids = [data.vocab.encode(s) for s in valid_sents]
    markers = style_markers(data.splits["train"], data.vocab, cfg.decode.style_ratio,
                            cfg.decode.style_min_count)
    extra: dict = {"best": -1.0, "best_step": -1, "best_acc": 0.0, "best_bleu": 0.0}
    valid_log = run.out_dir / "valid_log.csv"
    resumed = run.state["step"] if run.state and run.state["phase"] == "adversarial" else 0
    # on resume, the validations up to the checkpoint stay
    run.folder.open_log(valid_log.name, VALID_FIELDS,
                        keep=lambda row: resumed > 0 and int(row[0]) <= resumed).close()

    @stops_first
    def step(i: int) -> dict[str, float]:
        model.train()
        tau = temperature(i, tc.gumbel.tau_start, tc.gumbel.decay, tc.gumbel.every,
                          tc.gumbel.tau_min)
        batch = sampler.next()
        total, losses, (h_real, h_fake) = transfer_losses(model, batch, tau, tc.weights)
        _step(model, g_opt, total, tc.grad_clip)
        out = per_word(losses, batch) | {"tau": tau}
        if (i + 1) % tc.generator_steps_per_disc == 0:
            d_loss, d_acc = discriminator_loss(model, batch, h_real, h_fake)
            _step(model.discriminator, d_opt, d_loss, tc.grad_clip)
            out |= {"disc": d_loss.item(), "disc_acc": d_acc}
        return out

    def evaluate(at: int) -> None:
        outputs = transfer_ids(model, valid_ids, valid_labels, 1, cfg.decode.max_extra_words)
        words = [data.vocab.decode(o) for o in outputs]
        acc = accuracy(nets["classifier"], data.vocab, words, [1 - y for y in valid_labels])
        bleu = self_bleu(words, valid_sents)
        s = score(acc, bleu, tc.select_min_bleu)
        improved = s > extra["best"]
        if improved:
            extra.update(best=s, best_step=at, best_acc=acc, best_bleu=bleu)
            save_model(run.out_dir / STYLE_FILE, "style", data.vocab, cfg.model.model_dump(),
                       model, {"step": at, "valid_accuracy": acc, "valid_self_bleu": bleu,
                               "data": cfg.data.model_dump(mode="json"), "seed": tc.seed},
                       decode=cfg.decode.model_dump(), style_words=markers)
        with valid_log.open("a", newline="") as fh:
            csv.writer(fh).writerow([at, f"{acc:.4f}", f"{bleu:.2f}", f"{s:.2f}",
                                     int(improved), f"{run.wall():.1f}"])

    if not resumed and not data.fine_tuning:
        evaluate(0)  # the warm-up model competes too (not the start of a fine-tuning)
    fields = ["style", "rec", "adv", "cycle", "disc", "disc_acc", "tau"]
    run.loop("adversarial", tc.adversarial_steps, step, fields, {"g": g_opt, "d": d_opt},
             {"train": sampler}, extra, evaluate, tc.eval_every)
    if tc.adversarial_steps % tc.eval_every or extra["best_step"] < 0:
        evaluate(tc.adversarial_steps)  # the last step was not validated yet
    return {"selected": {"step": extra["best_step"], "valid_accuracy": extra["best_acc"],
                         "valid_self_bleu": extra["best_bleu"]}}


PHASE_FNS = {"classifier": phase_classifier, "lm": phase_lm, "pretrain": phase_pretrain,
             "reconstruct": phase_reconstruct, "adversarial": phase_adversarial}
