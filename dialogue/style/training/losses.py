"""The losses of thesis eqs. 3.8-3.14 on one mixed batch of negative and positive sentences.

A batch holds sentences of both styles with their labels l; each sentence is encoded with
its own style code E_y(l) and translated to the other style E_y(1 - l), so the two
directions of the thesis (x_1 -> x_2 and x_2 -> x_1) are trained together.
Sentence losses are summed over the words and averaged over the batch (Shen et al.'s scale).
"""

from __future__ import annotations

import torch
import torch.nn.functional as F  # noqa: N812

from dialogue.style.config import LossWeights
from dialogue.style.model import FAKE, StyleTransferModel
from textnets.batch import Batch
from textnets.functional import masked_nll
from textnets.vocab import BOS_ID


def pretrain_losses(model: StyleTransferModel, batch: Batch) -> dict[str, torch.Tensor]:
    """Eqs. 3.8-3.10: the style auto-encoder and E_z and G as style-conditioned LMs.

    During this phase G starts from ``[0, y]``: it learns the language of each style before
    it learns to use a content code.
    """
    y = model.style(batch.labels)
    emb = model.embedding(batch.inputs)
    table = model.embedding.weight
    lm_enc = masked_nll(model.encoder.lm_logits(model.encoder_inputs(batch.inputs), y, table),
                        batch.targets).mean()
    z0 = y.new_zeros(len(y), model.cfg.content_dim)
    _, logits = model.generator.teacher_force(emb, z0, y, table)
    lm_gen = masked_nll(logits, batch.targets).mean()
    return {"style": model.style.loss(batch.labels), "lm_enc": lm_enc, "lm_gen": lm_gen}


def soft_inputs(model: StyleTransferModel, words: torch.Tensor) -> torch.Tensor:
    """Encoder inputs ``<bos> w_1 .. w_{T-1}`` from relaxed one-hot words ``(B, T, V)``."""
    bos = model.embedding.weight[BOS_ID].expand(len(words), 1, -1)
    return torch.cat([bos, words[:, :-1] @ model.embedding.weight], 1)


def transfer_losses(model: StyleTransferModel, batch: Batch, tau: float, weights: LossWeights,
                    adversarial: bool = True
                    ) -> tuple[torch.Tensor, dict[str, torch.Tensor], tuple | None]:
    """The generator-side objective L_1 = w_s L_S + w_r L_rec + w_a L_G + w_c L_cycle.

    Returns the weighted total, the separate (unweighted) losses and, when ``adversarial``,
    the detached real and transferred hidden-state sequences for the discriminator step.
    Without ``adversarial`` only eqs. 3.8 and 3.11 are computed (the warm-up phase). With
    ``weights.per_word`` the sentence losses (rec, cycle) enter the total divided by the
    batch's mean sentence length, which strengthens the adversarial term by that factor.
    """
    labels = batch.labels
    flipped = 1 - labels
    y_src, y_tgt = model.style(labels), model.style(flipped)
    emb = model.embedding(batch.inputs)
    z, memory = model.content(model.encoder_inputs(batch.inputs), batch.lengths, y_src)
    h_real, logits = model.generator.teacher_force(emb, z, y_src, model.embedding.weight,
                                                   memory)
    losses = {"style": model.style.loss(labels),
              "rec": masked_nll(logits, batch.targets).mean()}  # eq. 3.11
    length = batch.mask.sum() / len(labels) if weights.per_word else 1.0
    if not adversarial:
        return weights.style * losses["style"] + weights.rec * losses["rec"] / length, losses, None
    steps = batch.inputs.shape[1]
    bos = model.embedding.weight[BOS_ID]
    h_fake, words = model.generator.free_run(model.embedding, bos, z, y_tgt, steps, tau,
                                             memory)
    # eq. 3.13, generator side: the transferred sentence should pass as the target style
    losses["adv"] = F.cross_entropy(model.discriminator(h_fake, batch.mask), flipped)
    # eq. 3.14: encode the transferred sentence in its new style, reconstruct the original
    z_cycle, memory_cycle = model.content(soft_inputs(model, model.mask_soft(words)),
                                          batch.lengths, y_tgt)
    _, logits_cycle = model.generator.teacher_force(emb, z_cycle, y_src,
                                                       model.embedding.weight, memory_cycle)
    losses["cycle"] = masked_nll(logits_cycle, batch.targets).mean()
    total = (weights.style * losses["style"] + weights.rec * losses["rec"] / length
             + weights.adv * losses["adv"] + weights.cycle * losses["cycle"] / length)
    return total, losses, (h_real.detach(), h_fake.detach())


def discriminator_loss(model: StyleTransferModel, batch: Batch, h_real: torch.Tensor,
                       h_fake: torch.Tensor) -> tuple[torch.Tensor, float]:
    """Eq. 3.13, discriminator side: real states -> their style, transferred -> fake.

    Returns the loss and the discriminator's accuracy on the 2B sequences.
    """
    x = torch.cat([h_real, h_fake])
    mask = torch.cat([batch.mask, batch.mask])
    target = torch.cat([batch.labels, torch.full_like(batch.labels, FAKE)])
    logits = model.discriminator(x, mask)
    acc = float((logits.argmax(1) == target).float().mean())
    return F.cross_entropy(logits, target), acc


