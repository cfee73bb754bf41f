"""The field's three measures of a style transfer, on tokenised sentences.

* transfer accuracy: the share of outputs the TextCNN classifier assigns the target style;
* content preservation: self-BLEU, corpus BLEU of the outputs against their inputs
  (sacreBLEU, default 13a tokenisation);
* fluency: perplexity of the outputs under the LSTM language model, per word with ``<eos>``
  counted (thesis eq. 4.2 pooled over the corpus).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import sacrebleu
import torch

from dialogue.style.nets import LanguageModel, SentimentClassifier
from textnets.batch import iterate_batches
from textnets.vocab import Vocab


@torch.no_grad()
def classify(net: SentimentClassifier, vocab: Vocab, sentences: Sequence[Sequence[str]],
             batch_size: int = 512) -> list[int]:
    """Predicted labels (0 negative, 1 positive)."""
    net.eval()
    order = sorted(range(len(sentences)), key=lambda i: len(sentences[i]))
    seqs = [vocab.encode(sentences[i]) for i in order]  # similar lengths batch together
    preds = [0] * len(seqs)
    done = 0
    for batch in iterate_batches(seqs, [0] * len(seqs), batch_size):
        for p in net(batch).argmax(1).tolist():
            preds[order[done]] = p
            done += 1
    return preds


def accuracy(net: SentimentClassifier, vocab: Vocab, sentences: Sequence[Sequence[str]],
             labels: Sequence[int]) -> float:
    """Share of ``sentences`` the classifier labels as ``labels``."""
    if not sentences:
        return float("nan")
    preds = classify(net, vocab, sentences)
    return sum(p == y for p, y in zip(preds, labels, strict=True)) / len(preds)


@torch.no_grad()
def perplexity(lm: LanguageModel, vocab: Vocab, sentences: Sequence[Sequence[str]],
               batch_size: int = 512) -> float:
    """Corpus perplexity ``exp(total NLL / total predicted words)`` (``<eos>`` included)."""
    lm.eval()
    seqs = sorted((vocab.encode(s) for s in sentences), key=len)
    nll, words = 0.0, 0.0
    for batch in iterate_batches(seqs, [0] * len(seqs), batch_size):
        nll += float(lm(batch).sum())
        words += float(batch.mask.sum())
    return math.exp(nll / words) if words else float("nan")


def self_bleu(outputs: Sequence[Sequence[str]], inputs: Sequence[Sequence[str]]) -> float:
    """Corpus BLEU (0-100) of the outputs with their own inputs as the single reference."""
    hyps = [" ".join(s) for s in outputs]
    refs = [" ".join(s) for s in inputs]
    return float(sacrebleu.corpus_bleu(hyps, [refs], force=True).score)

