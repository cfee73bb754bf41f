"""Evaluating the chit-chat bot on its held-out test conversations.

* **Perplexity** (thesis eq. 4.2), per token: ``exp(-(1/N) sum log p(w_i | w_<i, utterance))``
  over every reply token and the closing ``<eos>`` of the test pairs; padding is excluded.
  Unlike the thesis's 1.14 (measured on its training data) this is on unseen conversations.
* **Unigram baseline**: the same test tokens under an add-one smoothed unigram model of the
  training replies (and their ``<eos>``) over the model's vocabulary less ``<pad>``/``<bos>``.
* For plain beam search (``decoded_reply``) and for the ranking the robot uses (``reply``):
  **generic share** (replies whose every sentence is a listed generic reply, ``rank.generic``),
  **distinct-1/2** (distinct uni-/bigrams over all uni-/bigrams of the test replies),
  **latency** (median wall time of one call) and, with ``relevance``, the mean cosine of the
  MiniLM sentence embeddings of line and reply (:mod:`.relevance`); the reference replies'
  relevance is the ceiling to compare with.
"""

from __future__ import annotations

import math
import statistics
import time
from collections import Counter
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import torch

from dialogue.chat.batch import batches
from dialogue.chat.config import ChatDataConfig, load_chat_config
from dialogue.chat.model import ChitChatModel
from dialogue.chat.rank import generic_replies, generic_share
from dialogue.chat.text import Pair, detokenize, tokenize
from dialogue.chat.training.data import load_chat_data
from dialogue.chat.training.relevance import SentenceEmbedder
from textnets.vocab import EOS_ID, Vocab

PROMPTS = ("Hello!", "How are you?", "What is your name?", "Do you like music?",
           "Tell me a joke.", "I feel sad today.", "What do you do for fun?", "Good night!")


@torch.no_grad()
def perplexity(net: torch.nn.Module, pairs: Sequence[Pair], vocab: Vocab,
               batch_size: int = 64) -> float:
    """Per-token perplexity of the replies given their utterances (teacher forced)."""
    was_training = net.training
    net.eval()
    nll, n = 0.0, 0
    for batch in batches(pairs, vocab, batch_size):
        s, k = net.token_nll(batch)
        nll, n = nll + s.item(), n + k
    net.train(was_training)
    return math.exp(nll / n) if n else math.nan


def unigram_perplexity(train: Sequence[Pair], test: Sequence[Pair], vocab: Vocab) -> float:
    """Perplexity of the test reply tokens under an add-one unigram of the training replies."""
    counts = Counter(i for _, tgt in train for i in (*vocab.encode(tgt), EOS_ID))
    size = len(vocab) - 2  # <pad> and <bos> are never predicted
    total = sum(counts.values()) + size
    ids = [i for _, tgt in test for i in (*vocab.encode(tgt), EOS_ID)]
    nll = -sum(math.log((counts[i] + 1) / total) for i in ids)
    return math.exp(nll / len(ids)) if ids else math.nan


def distinct_n(replies: Sequence[Sequence[str]], n: int) -> float:
    """Distinct n-grams over all n-grams of ``replies`` (0 when there are none)."""
    grams = [tuple(r[i:i + n]) for r in replies for i in range(len(r) - n + 1)]
    return len(set(grams)) / len(grams) if grams else 0.0


def examples_table(rows: Sequence[tuple[str, str, str, str]]) -> str:
    """A markdown table of ``(person, reference, beam reply, ranked reply)`` exchanges."""
    def cell(s: str) -> str:
        return s.replace("|", "\\|") or "—"

    lines = ["| person | reference reply | beam search alone | ranked (the robot) |",
             "| --- | --- | --- | --- |"]
    lines += [f"| {' | '.join(cell(c) for c in row)} |" for row in rows]
    return "\n".join(lines)


def reply_figures(lines: Sequence[str], replies: Sequence[str], times: Sequence[float],
                  generic: set[tuple[str, ...]],
                  embedder: SentenceEmbedder | None) -> dict[str, float]:
    """Generic share, distinct-1/2, latency and (with an embedder) mean relevance of one
    decoding's replies to ``lines``."""
    tokenised = [tokenize(r) for r in replies]
    out = {"generic_share": statistics.fmean(generic_share(t, generic) == 1.0
                                             for t in tokenised) if replies else math.nan,
           "distinct_1": distinct_n(tokenised, 1), "distinct_2": distinct_n(tokenised, 2),
           "latency_ms_median": statistics.median(times) if times else math.nan}
    if embedder is not None:
        out["relevance"] = statistics.fmean(embedder.cosines(lines, replies))
    return out


def timed_replies(reply: Callable[[str], str], lines: Sequence[str]) -> tuple[list[str],
                                                                             list[float]]:
    """Each line's reply and its wall time in milliseconds."""
    replies, times = [], []
    for text in lines:
        t0 = time.perf_counter()
        replies.append(reply(text))
        times.append((time.perf_counter() - t0) * 1000)
    return replies, times


def evaluate(model: Any, train: Sequence[Pair], test: Sequence[Pair], n_examples: int = 12,
             embedder: SentenceEmbedder | None = None) -> dict[str, Any]:
    """All metrics of a :class:`~dialogue.chat.model.ChitChatModel` on ``test``: perplexity,
    and for plain beam search and for the ranking the figures of :func:`reply_figures`
    (relevance, and the references' relevance, only with an ``embedder``)."""
    vocab = model.vocab
    lines = [detokenize(src) for src, _ in test]
    generic = generic_replies(load_chat_config().rank.generic)
    decodings = {}
    replies = {}
    for name, reply in (("beam", model.decoded_reply), ("ranked", model.reply)):
        replies[name], times = timed_replies(reply, lines)
        decodings[name] = reply_figures(lines, replies[name], times, generic, embedder)
    references = [detokenize(tgt) for _, tgt in test]
    rows = [(a, b, c, d) for a, b, c, d in zip(lines, references, replies["beam"],
                                               replies["ranked"], strict=True)][:n_examples]
    rows += [(p, "", model.decoded_reply(p), model.reply(p)) for p in PROMPTS]
    chat_ppl = perplexity(model.net, test, vocab)
    uni_ppl = unigram_perplexity(train, test, vocab)
    result = {"chat_perplexity": chat_ppl, "unigram_perplexity": uni_ppl,
              "perplexity_ratio": uni_ppl / chat_ppl, **decodings["ranked"],
              "decodings": decodings, "test_pairs": len(test),
              "test_tokens": sum(len(t) + 1 for _, t in test),
              "examples": [dict(zip(("input", "reference", "beam", "reply"), r, strict=True))
                           for r in rows],
              "examples_markdown": examples_table(rows)}
    if embedder is not None:
        result["reference_relevance"] = statistics.fmean(embedder.cosines(lines, references))
    return result


def evaluate_file(path: str | Path, n_examples: int = 12,
                  relevance: bool = False) -> dict[str, Any]:
    """Load a model file, rebuild its data split from the stored config and evaluate it
    (``relevance``: also embed lines and replies, which loads the MiniLM model)."""
    model = ChitChatModel.load(path)
    embedder = SentenceEmbedder() if relevance else None
    data = load_chat_data(ChatDataConfig(**model.config["data"]))
    threads = torch.get_num_threads()
    torch.set_num_threads(1)  # latency as on the robot's single inference thread
    try:
        result = evaluate(model, data.splits["train"], data.splits["test"], n_examples,
                          embedder)
    finally:
        torch.set_num_threads(threads)
    result["model_mb"] = Path(path).stat().st_size / 2**20
    result["meta"] = model.meta
    return result
