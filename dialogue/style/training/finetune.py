"""Fine-tuning the transfer model on conversation: the conversational lines added to its
training set (labelled by the sentiment judge) and the start from a shipped ``style.pt``.
See :mod:`dialogue.style.training.conversation` and docs/style_transfer.md."""

from __future__ import annotations

from pathlib import Path

from dialogue.style.config import StyleConfig
from dialogue.style.files import StyleModelError, load_transfer
from dialogue.style.model import StyleTransferModel
from dialogue.style.nets import SentimentClassifier
from dialogue.style.training.conversation import training_lines
from dialogue.style.training.metrics import classify
from textnets.vocab import Vocab


def conversation_set(cfg: StyleConfig, vocab: Vocab, judge: SentimentClassifier
                     ) -> tuple[list[list[int]], list[int], dict]:
    """The conversational lines of ``cfg.conversation`` as ids, each ``repeat`` times, their
    labels by ``judge``, and their counts for the summary."""
    lines = training_lines(cfg.conversation)
    labels = classify(judge, vocab, lines) if lines else []
    n = cfg.conversation.repeat
    return ([vocab.encode(s) for s in lines] * n, labels * n,
            {"conversation": {"lines": len(lines), "positive": sum(labels), "repeat": n}})


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
