"""Evaluating the chit-chat bot on its held-out test conversations.

* **Perplexity** (thesis eq. 4.2), per token: ``exp(-(1/N) sum log p(w_i | w_<i, utterance))``
  over every reply token and the closing ``<eos>`` of the test pairs; padding is excluded.
  Unlike the thesis's 1.14 (measured on its training data) this is on unseen conversations.
* **Unigram baseline**: the same test tokens under an add-one smoothed unigram model of the
  training replies (and their ``<eos>``) over the model's vocabulary less ``<pad>``/``<bos>``.
* **distinct-1/2**: distinct uni-/bigrams over all uni-/bigrams of the generated test replies.
* **Latency**: median wall time of one ``reply()`` call (tokenise, decode, detokenise).
"""

from __future__ import annotations

import math
import statistics
import time
from collections import Counter
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import torch

from dialogue.chat.batch import batches
from dialogue.chat.config import ChatDataConfig
from dialogue.chat.model import ChitChatModel
from dialogue.chat.text import Pair, detokenize, tokenize
from dialogue.chat.training.data import load_chat_data
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


def examples_table(rows: Sequence[tuple[str, str, str]]) -> str:
    """A markdown table of ``(person, reference, robot)`` exchanges."""
    def cell(s: str) -> str:
        return s.replace("|", "\\|") or "—"

    lines = ["| person | reference reply | robot |", "| --- | --- | --- |"]
    lines += [f"| {cell(a)} | {cell(b)} | {cell(c)} |" for a, b, c in rows]
    return "\n".join(lines)


def evaluate(model: Any, train: Sequence[Pair], test: Sequence[Pair],
             n_examples: int = 12) -> dict[str, Any]:
    """All metrics of a :class:`~dialogue.chat.model.ChitChatModel` on ``test``."""
    vocab = model.vocab
    replies, times, rows = [], [], []
    for i, (src, tgt) in enumerate(test):
        text = detokenize(src)
        t0 = time.perf_counter()
        reply = model.reply(text)
        times.append((time.perf_counter() - t0) * 1000)
        replies.append(reply)
        if i < n_examples:
            rows.append((text, detokenize(tgt), reply))
    rows += [(p, "", model.reply(p)) for p in PROMPTS]
    tokenised = [tokenize(r) for r in replies]
    chat_ppl = perplexity(model.net, test, vocab)
    uni_ppl = unigram_perplexity(train, test, vocab)
    return {"chat_perplexity": chat_ppl, "unigram_perplexity": uni_ppl,
            "perplexity_ratio": uni_ppl / chat_ppl,
            "distinct_1": distinct_n(tokenised, 1), "distinct_2": distinct_n(tokenised, 2),
            "latency_ms_median": statistics.median(times) if times else math.nan,
            "test_pairs": len(test),
            "test_tokens": sum(len(t) + 1 for _, t in test),
            "examples": [{"input": a, "reference": b, "reply": c} for a, b, c in rows],
            "examples_markdown": examples_table(rows)}


def evaluate_file(path: str | Path, n_examples: int = 12) -> dict[str, Any]:
    """Load a model file, rebuild its data split from the stored config and evaluate it."""
    model = ChitChatModel.load(path)
    data = load_chat_data(ChatDataConfig(**model.config["data"]))
    threads = torch.get_num_threads()
    torch.set_num_threads(1)  # latency as on the robot's single inference thread
    try:
        result = evaluate(model, data.splits["train"], data.splits["test"], n_examples)
    finally:
        torch.set_num_threads(threads)
    result["model_mb"] = Path(path).stat().st_size / 2**20
    result["meta"] = model.meta
    return result
