"""Decoding a transfer: the sentence is encoded in its own style and generated in the other.

Thesis §3.3.2: at test time E_z receives the source style code and G the target style code.
:func:`greedy` takes the most likely word at each step; :func:`beam_search` keeps the
``beam_size`` best partial sentences and picks the finished one with the best mean word
log-probability plus ``disc_weight`` times the log-probability that the model's own N+1
discriminator gives the target style. Sentences stop at ``<eos>`` or after
``source words + max_extra_words`` words.
"""

from __future__ import annotations

import torch

from dialogue.style.model import StyleTransferModel
from textnets.batch import Batch, make_batch
from textnets.copy import Memory, select
from textnets.vocab import BOS_ID, EOS_ID, PAD_ID

NEG_INF = float("-inf")


def _start(model: StyleTransferModel, batch: Batch, target: torch.Tensor):
    z, memory = model.encode(batch.inputs, batch.lengths, batch.labels)
    return model.generator.initial(z, model.style(target)), z, memory


def _word_logp(model: StyleTransferModel, h: torch.Tensor, memory: Memory | None
               ) -> torch.Tensor:
    logits = model.generator.logits(h, model.embedding.weight, memory)
    logits[:, PAD_ID] = NEG_INF
    logits[:, BOS_ID] = NEG_INF
    return torch.log_softmax(logits, -1)


@torch.no_grad()
def greedy(model: StyleTransferModel, batch: Batch, target: torch.Tensor,
           max_extra_words: int) -> list[list[int]]:
    """Greedy transfer of every sentence of ``batch`` to the styles ``target`` ``(B,)``."""
    state, _, memory = _start(model, batch, target)
    limit = batch.lengths - 1 + max_extra_words
    x = model.embedding.weight[BOS_ID].expand(len(target), -1)
    words: list[torch.Tensor] = []
    done = torch.zeros(len(target), dtype=torch.bool)
    for t in range(int(limit.max()) + 1):
        state = model.generator.step(x, state)
        logp = _word_logp(model, state[0], memory)
        w = logp.argmax(1)
        w = torch.where(limit <= t, torch.full_like(w, EOS_ID), w)
        words.append(torch.where(done, torch.full_like(w, PAD_ID), w))
        done |= w == EOS_ID
        if bool(done.all()):
            break
        x = model.embedding(w)
    out = torch.stack(words, 1).tolist()
    return [[i for i in row if i not in (PAD_ID, EOS_ID)] for row in out]


@torch.no_grad()
def beam_search(model: StyleTransferModel, batch: Batch, target: torch.Tensor,
                beam_size: int, max_extra_words: int, disc_weight: float = 0.0
                ) -> list[list[int]]:
    """Beam-search transfer with optional reranking by the discriminator (module docstring)."""
    b, k = len(target), beam_size
    (h, c), z, memory = _start(model, batch, target)
    h, c = h.repeat_interleave(k, 0), c.repeat_interleave(k, 0)
    # the beams of one sentence share its memory
    beam_memory = select(memory, torch.arange(b).repeat_interleave(k))
    limit = (batch.lengths - 1 + max_extra_words).repeat_interleave(k)
    scores = torch.full((b, k), NEG_INF)
    scores[:, 0] = 0.0
    seqs = torch.zeros(b * k, 0, dtype=torch.long)
    finished: list[list[tuple[float, list[int]]]] = [[] for _ in range(b)]
    x = model.embedding.weight[BOS_ID].expand(b * k, -1)
    for t in range(int(limit.max()) + 1):
        h, c = model.generator.step(x, (h, c))
        logp = _word_logp(model, h, beam_memory)
        over = limit <= t  # out of words: only <eos> is allowed
        logp[over] = torch.where(torch.arange(logp.shape[1]) == EOS_ID, 0.0, NEG_INF)
        cand = (scores.view(-1, 1) + logp).view(b, -1)
        top, idx = cand.topk(k, 1)
        beam = (idx // logp.shape[1]) + torch.arange(b)[:, None] * k
        word = idx % logp.shape[1]
        h, c, seqs = h[beam.view(-1)], c[beam.view(-1)], seqs[beam.view(-1)]
        seqs = torch.cat([seqs, word.view(-1, 1)], 1)
        scores = top.clone()
        for i, j in (word == EOS_ID).nonzero().tolist():
            if top[i, j] > NEG_INF:
                finished[i].append((float(top[i, j]), seqs[i * k + j, :-1].tolist()))
            scores[i, j] = NEG_INF
        if all(len(f) >= k for f in finished) or bool((scores == NEG_INF).all()):
            break
        x = model.embedding(word.view(-1))
    return _choose(model, z, memory, target, finished, disc_weight)


def _choose(model: StyleTransferModel, z: torch.Tensor, memory: Memory | None,
            target: torch.Tensor, finished: list[list[tuple[float, list[int]]]],
            disc_weight: float) -> list[list[int]]:
    flat = [(i, s / (len(w) + 1), w) for i, f in enumerate(finished) for s, w in f]
    if not flat:
        return [[] for _ in finished]
    bonus = torch.zeros(len(flat))
    if disc_weight > 0:
        rows = torch.tensor([i for i, _, _ in flat])
        cand = make_batch([w for _, _, w in flat], target[rows].tolist())
        y = model.style(cand.labels)
        hidden, _ = model.generator.teacher_force(
            model.embedding(cand.inputs), z[rows], y, model.embedding.weight,
            select(memory, rows))
        logd = torch.log_softmax(model.discriminator(hidden, cand.mask), 1)
        bonus = disc_weight * logd[torch.arange(len(flat)), cand.labels]
    best: list[tuple[float, list[int]]] = [(NEG_INF, []) for _ in finished]
    for (i, score, words), extra in zip(flat, bonus.tolist(), strict=True):
        if score + extra > best[i][0]:
            best[i] = (score + extra, words)
    return [w for _, w in best]


def transfer_ids(model: StyleTransferModel, seqs: list[list[int]], source: list[int],
                 beam_size: int, max_extra_words: int, disc_weight: float = 0.0,
                 batch_size: int = 256) -> list[list[int]]:
    """Transfer id sequences written in styles ``source`` to the opposite styles."""
    model.eval()
    out: list[list[int]] = []
    for start in range(0, len(seqs), batch_size):
        batch = make_batch(seqs[start:start + batch_size], source[start:start + batch_size])
        target = 1 - batch.labels
        if beam_size == 1:
            out += greedy(model, batch, target, max_extra_words)
        else:
            out += beam_search(model, batch, target, beam_size, max_extra_words, disc_weight)
    return out
