"""Fine-tuning the transfer model on conversation: the conversational lines added to its
training set (labelled by the sentiment judge) and the start from a shipped ``style.pt``.
See :mod:`dialogue.style.training.conversation` and docs/style_transfer.md."""

from __future__ import annotations

from pathlib import Path

import torch

from dialogue.style.config import StyleConfig
from dialogue.style.files import StyleModelError, load_transfer
from dialogue.style.model import StyleTransferModel
from dialogue.style.nets import SentimentClassifier
from dialogue.style.training.conversation import training_lines
from textnets.batch import make_batch
from textnets.vocab import Vocab


@torch.no_grad()
def judged(judge: SentimentClassifier, vocab: Vocab, lines: list[list[str]],
           batch_size: int = 256) -> list[tuple[int, float]]:
    """The judge's label of each line and its probability."""
    judge.eval()
    out: list[tuple[int, float]] = []
    for i in range(0, len(lines), batch_size):
        chunk = lines[i:i + batch_size]
        probs = judge(make_batch([vocab.encode(s) for s in chunk], [0] * len(chunk))).softmax(1)
        conf, label = probs.max(1)
        out += zip(label.tolist(), conf.tolist(), strict=True)
    return out


def conversation_set(cfg: StyleConfig, vocab: Vocab, judge: SentimentClassifier
                     ) -> tuple[list[list[int]], list[int], dict]:
    """The conversational lines of ``cfg.conversation`` that the judge labels with at least
    ``min_confidence``, as ids, each ``repeat`` times; their labels; their counts."""
    c = cfg.conversation
    lines = training_lines(c)
    kept = [(s, y) for s, (y, p) in zip(lines, judged(judge, vocab, lines), strict=True)
            if p >= c.min_confidence]
    labels = [y for _, y in kept]
    return ([vocab.encode(s) for s, _ in kept] * c.repeat, labels * c.repeat,
            {"conversation": {"lines": len(lines), "kept": len(kept), "positive": sum(labels),
                              "repeat": c.repeat}})


def start_from(model: StyleTransferModel, vocab: Vocab, init: Path) -> None:
    """Load the weights of the transfer model file ``init`` (same vocabulary and sizes): a
    fine-tuning run starts from it instead of from scratch."""
    start, start_vocab, _, _ = load_transfer(init)
    if start_vocab.itos != vocab.itos:
        raise StyleModelError(f"{init}: trained with another vocabulary than this data's")
    try:
        model.load_state_dict(start.state_dict())
    except RuntimeError as exc:
        raise StyleModelError(f"{init}: other model sizes than the config's ({exc})") from None
