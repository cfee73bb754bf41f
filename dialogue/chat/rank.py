"""Choosing a chit-chat reply: candidates from the seq2seq's beam and from the training pairs,
ranked by the seq2seq itself plus relevance, less a penalty for generic replies.

Beam search alone favours replies that fit any line ("I'm not sure."), because they are
likely after every input. Here the candidates are

* the ``beam_candidates`` best finished beam replies, and
* the replies of the ``retrieve`` training pairs whose inputs are most similar to the line
  (TF-IDF cosine over words, at least ``min_similarity``), from the pool shipped beside the
  model (:mod:`dialogue.chat.pool`: training pairs only, read in place),

and each scores ``model * log p(reply | line) / tokens ** length_penalty`` (the decoding's
length penalty, ``<eos>`` counted: the beam's own scores, and the retrieved replies teacher
forced through the seq2seq) ``+ match * similarity(line, its training input)``
(0 for beam replies) ``+ topic * similarity(line, reply) - generic_penalty * share``, where
``share`` is the part of the reply's sentences that are, word for word, replies listed under
``rank.generic`` in ``config/chat.yaml`` ("I'm not sure. I don't know." has 1).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import torch
from sklearn.feature_extraction.text import TfidfVectorizer

from dialogue.chat.batch import make_batch
from dialogue.chat.config import ChatDecodeConfig, ChatRankConfig
from dialogue.chat.decode import beam_hypotheses
from dialogue.chat.seq2seq import Seq2Seq
from dialogue.chat.text import Pair, tokenize
from textnets.vocab import UNK_ID, Vocab

Tokens = tuple[str, ...]


def words(tokens: Sequence[str]) -> list[str]:
    """The word tokens of ``tokens`` (punctuation and ``<unk>`` left out)."""
    return [t for t in tokens if t[:1].isalnum()]


def sentences(tokens: Sequence[str]) -> list[tuple[str, ...]]:
    """The word tuples of each sentence of ``tokens`` (split after ``.``, ``!`` and ``?``)."""
    out, current = [], []
    for t in tokens:
        if t in (".", "!", "?"):
            out.append(tuple(current))
            current = []
        elif t[:1].isalnum():
            current.append(t)
    return [s for s in [*out, tuple(current)] if s]


def generic_share(tokens: Sequence[str], generic: set[tuple[str, ...]]) -> float:
    """The share of the reply's sentences that are generic replies (1.0 when the whole
    reply is one)."""
    if tuple(words(tokens)) in generic:
        return 1.0
    parts = sentences(tokens)
    return sum(p in generic for p in parts) / len(parts) if parts else 0.0


def generic_replies(texts: Sequence[str]) -> set[tuple[str, ...]]:
    """The word tuples of the configured generic replies and of each of their sentences."""
    return {s for t in texts for s in (tuple(words(tokenize(t))), *sentences(tokenize(t)))}


@dataclass(frozen=True)
class Candidate:
    """One possible reply with the parts of its score."""

    tokens: Tokens
    source: str       # "beam" or "retrieved"
    log_p: float      # length-normalised log p(reply | line) under the seq2seq
    match: float      # similarity of the line to the training input this reply answered
    topic: float      # similarity of the line to the reply
    generic: float    # share of its sentences that are generic replies
    score: float


@torch.no_grad()
def reply_log_probs(net: Seq2Seq, vocab: Vocab, src_ids: Sequence[int],
                    replies: Sequence[Sequence[str]], length_penalty: float) -> list[float]:
    """``log p(reply | line) / tokens ** length_penalty`` for each reply, teacher forced in
    one batch (the line is encoded once)."""
    if not replies:
        return []
    batch = make_batch([((), tuple(r)) for r in replies], vocab)
    src = torch.tensor([list(src_ids)], dtype=torch.long)
    mask = torch.ones_like(src, dtype=torch.bool)
    enc_out, (h, c) = net.encode(src, mask)
    k = len(replies)
    state = (h.expand(-1, k, -1).contiguous(), c.expand(-1, k, -1).contiguous())
    att = net.attend(batch.tgt_in, state, enc_out.expand(k, -1, -1), mask.expand(k, -1))[0]
    real = batch.tgt_mask  # the output layer only where there are reply tokens: the most work
    logp = torch.log_softmax(net.logits(att[real]).float(), dim=-1)
    token = torch.zeros(real.shape)
    token[real] = logp.gather(-1, batch.tgt_out[real][:, None])[:, 0]
    n = real.sum(1).float()
    return (token.sum(1) / n ** length_penalty).tolist()


class ReplyRanker:
    """Candidates and scores for one line; see the module doc."""

    def __init__(self, net: Seq2Seq, vocab: Vocab, pool: Sequence[Pair], cfg: ChatRankConfig,
                 decode: ChatDecodeConfig) -> None:
        self.net, self.vocab, self.cfg, self.decode = net, vocab, cfg, decode
        self.pool = list(pool)
        self.generic = generic_replies(cfg.generic)
        self.tfidf = TfidfVectorizer(analyzer=words, sublinear_tf=True)
        if self.pool and cfg.retrieve:
            self.tfidf.fit([side for pair in self.pool for side in pair])
            self.inputs = self.tfidf.transform([src for src, _ in self.pool])

    def retrieve(self, line: Sequence[str]) -> dict[Tokens, float]:
        """Replies of the most similar training inputs, with that similarity (the best one
        when a reply answers several)."""
        if not self.pool or not self.cfg.retrieve:
            return {}
        sims = (self.inputs @ self.tfidf.transform([list(line)]).T).toarray()[:, 0]
        k = min(self.cfg.retrieve, len(sims))
        found: dict[Tokens, float] = {}
        for i in sorted(np.argpartition(-sims, k - 1)[:k], key=lambda i: (-sims[i], i)):
            if sims[i] >= self.cfg.min_similarity:
                reply = self.pool[i][1]
                found[reply] = max(found.get(reply, 0.0), float(sims[i]))
        return found

    def topic(self, text: Sequence[str], replies: Sequence[Tokens]) -> list[float]:
        """TF-IDF cosine of ``text`` with each reply (0 without a fitted pool)."""
        if not self.pool or not self.cfg.retrieve:
            return [0.0] * len(replies)
        rows = self.tfidf.transform([list(r) for r in replies])
        return (rows @ self.tfidf.transform([list(text)]).T).toarray()[:, 0].tolist()

    def candidates(self, line: Sequence[str], topic: Sequence[str]) -> list[Candidate]:
        """All candidates for ``line`` (tokens, already cut to the model's length) with their
        scores, best first; ``topic`` is what the topic term compares replies with (the line,
        or more for a follow-up)."""
        cfg = self.cfg
        src_ids = self.vocab.encode(line) or [UNK_ID]
        log_p: dict[Tokens, float] = {}  # the beam's own scores are log p / length ** penalty
        for score, ids in beam_hypotheses(self.net, src_ids, self.decode)[:cfg.beam_candidates]:
            log_p.setdefault(tuple(self.vocab.decode(ids, skip_unknown=True)), score)
        log_p.pop((), None)
        found = self.retrieve(line)
        new = [r for r in found if r not in log_p]
        log_p.update(zip(new, reply_log_probs(self.net, self.vocab, src_ids, new,
                                              self.decode.length_penalty), strict=True))
        replies = list(log_p)
        out = []
        for reply, top in zip(replies, self.topic(topic, replies), strict=True):
            lp, match = log_p[reply], found.get(reply, 0.0)
            source = "retrieved" if reply in found else "beam"
            generic = generic_share(reply, self.generic)
            score = (cfg.model * lp + cfg.match * match + cfg.topic * top
                     - cfg.generic_penalty * generic)
            out.append(Candidate(reply, source, lp, match, top, generic, score))
        return sorted(out, key=lambda c: -c.score)
