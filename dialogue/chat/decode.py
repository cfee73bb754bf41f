"""Decoding replies from :class:`~dialogue.chat.model.Seq2Seq`: beam search or top-p sampling.

Both never emit ``<pad>``, ``<bos>`` or ``<unk>``, forbid ``<eos>`` before ``min_len`` tokens
and block repeated n-grams: a token that would complete an n-gram already in the reply
(``no_repeat_ngram`` = n) is not allowed. Beam search ranks finished replies by
``log p / length ** length_penalty`` (length counts ``<eos>``).
"""

from __future__ import annotations

import torch

from dialogue.chat.config import ChatDecodeConfig
from dialogue.chat.seq2seq import Seq2Seq, State
from textnets.vocab import BOS_ID, EOS_ID, PAD_ID, UNK_ID

NEG_INF = float("-inf")


def banned_ngram_tokens(tokens: list[int], n: int) -> set[int]:
    """Tokens that would repeat an n-gram of ``tokens`` if appended."""
    if n <= 0 or len(tokens) < n:
        return set()
    if n == 1:
        return set(tokens)
    prefix = tuple(tokens[len(tokens) - n + 1:])
    return {tokens[i + n - 1] for i in range(len(tokens) - n + 1)
            if tuple(tokens[i:i + n - 1]) == prefix}


def _mask(logp: torch.Tensor, hyps: list[list[int]], step: int,
          cfg: ChatDecodeConfig) -> torch.Tensor:
    """Disallowed tokens of every hypothesis set to -inf (``hyps`` exclude ``<bos>``)."""
    logp[:, [PAD_ID, BOS_ID, UNK_ID]] = NEG_INF
    if step < cfg.min_len:
        logp[:, EOS_ID] = NEG_INF
    if step >= cfg.max_len:  # only <eos> is left
        keep = logp[:, EOS_ID].clone()
        logp.fill_(NEG_INF)
        logp[:, EOS_ID] = keep
    for row, toks in enumerate(hyps):
        banned = banned_ngram_tokens(toks, cfg.no_repeat_ngram)
        if banned:
            logp[row, list(banned)] = NEG_INF
    return logp


def _start(net: Seq2Seq, src_ids: list[int]) -> tuple[torch.Tensor, torch.Tensor, State]:
    src = torch.tensor([src_ids], dtype=torch.long)
    mask = torch.ones_like(src, dtype=torch.bool)
    enc_out, state = net.encode(src, mask)
    return enc_out, mask, state


def _step(net: Seq2Seq, last: list[int], state: State, enc_out: torch.Tensor,
          mask: torch.Tensor) -> tuple[torch.Tensor, State]:
    k = len(last)
    tok = torch.tensor(last, dtype=torch.long)
    logits, state = net.step(tok, state, enc_out.expand(k, -1, -1), mask.expand(k, -1))
    return torch.log_softmax(logits.float(), dim=-1), state


def beam_search(net: Seq2Seq, src_ids: list[int], cfg: ChatDecodeConfig) -> list[int]:
    """The best reply (ids without ``<bos>``/``<eos>``) by length-normalised beam search."""
    return beam_hypotheses(net, src_ids, cfg)[0][1]


@torch.no_grad()
def beam_hypotheses(net: Seq2Seq, src_ids: list[int],
                    cfg: ChatDecodeConfig) -> list[tuple[float, list[int]]]:
    """Every finished beam reply with its normalised score, best first (the reply ranking
    takes several of them as candidates)."""
    enc_out, mask, state = _start(net, src_ids)
    hyps: list[list[int]] = [[]]
    scores = torch.zeros(1)
    finished: list[tuple[float, list[int]]] = []
    k = cfg.beam_size
    for step in range(cfg.max_len + 1):
        last = [h[-1] if h else BOS_ID for h in hyps]
        logp, state = _step(net, last, state, enc_out, mask)
        logp = _mask(logp, hyps, step, cfg)
        total = (scores[:, None] + logp).view(-1)
        top_scores, top_idx = total.topk(min(2 * k, total.numel()))
        new_hyps, new_scores, rows = [], [], []
        for score, idx in zip(top_scores.tolist(), top_idx.tolist(), strict=True):
            if score == NEG_INF:
                break
            row, tok = divmod(idx, logp.shape[1])
            if tok == EOS_ID:
                length = len(hyps[row]) + 1
                finished.append((score / length ** cfg.length_penalty, hyps[row]))
            else:
                new_hyps.append([*hyps[row], tok])
                new_scores.append(score)
                rows.append(row)
            if len(new_hyps) == k:
                break
        if len(finished) >= k or not new_hyps:
            break
        hyps, scores = new_hyps, torch.tensor(new_scores)
        index = torch.tensor(rows)
        state = (state[0][:, index], state[1][:, index])
    if not finished:
        return [(float(scores[0]), hyps[0])]
    return sorted(finished, key=lambda f: -f[0])


@torch.no_grad()
def sample(net: Seq2Seq, src_ids: list[int], cfg: ChatDecodeConfig,
           generator: torch.Generator | None = None) -> list[int]:
    """One reply drawn by nucleus (top-p) sampling at ``cfg.temperature``."""
    enc_out, mask, state = _start(net, src_ids)
    out: list[int] = []
    for step in range(cfg.max_len + 1):
        logp, state = _step(net, [out[-1] if out else BOS_ID], state, enc_out, mask)
        logp = _mask(logp, [out], step, cfg)[0]
        if torch.isinf(logp).all():
            break
        probs = torch.softmax(logp / cfg.temperature, dim=-1)
        sorted_p, order = probs.sort(descending=True)
        keep = (sorted_p.cumsum(0) - sorted_p) < cfg.top_p  # always keeps the first
        sorted_p = sorted_p * keep
        choice = torch.multinomial(sorted_p / sorted_p.sum(), 1, generator=generator)
        tok = int(order[choice])
        if tok == EOS_ID:
            break
        out.append(tok)
    return out
