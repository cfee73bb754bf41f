"""Model files of the style-transfer system: writing them atomically and loading them safely.

A model folder holds three files, each loadable with ``torch.load(weights_only=True)``:
``style.pt`` (the transfer model), ``classifier.pt`` (the TextCNN judge) and ``lm.pt`` (the
fluency language model). Each stores its vocabulary, its config section and its weights.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from torch import nn

from core.checkpoint import atomic_torch_save, read_weights
from core.errors import UserError
from dialogue.style.config import (
    ClassifierConfig,
    DecodeConfig,
    LMConfig,
    ModelConfig,
)
from dialogue.style.model import StyleTransferModel
from dialogue.style.nets import LanguageModel, SentimentClassifier
from textnets.vocab import Vocab

FORMAT = "companion-style-1"
_STOPWORDS_TEXT = (
    "a an the and or but if so of to in on at by for with from as is are was were be been am "
    "it its it 's this that these those there here i me my we our you your he him his she her "
    "they them their what which who whom when where why how all any both each few more most "
    "other some such no nor not n't only own same than too very can will just do does did "
    "have has had would should could ca wo 's 're 've 'm 'll 'd _num_ again also about up out "
    "then once")
STOPWORDS = frozenset(_STOPWORDS_TEXT.split())


class StyleModelError(UserError):
    """A style-transfer model file is missing, unreadable or inconsistent."""


def save_model(path: Path, kind: str, vocab: Vocab, config: dict[str, Any],
               module: nn.Module, meta: dict[str, Any], **extra: Any) -> None:
    """Write one model file (plain containers and tensors only)."""
    atomic_torch_save({"format": FORMAT, "kind": kind, "vocab": list(vocab.itos),
                       "config": config, "state_dict": module.state_dict(), "meta": meta,
                       **extra}, path)


def read_model_file(path: Path, kind: str) -> dict[str, Any]:
    """The stored dict of a model file, checked for its kind."""
    blob = read_weights(path, StyleModelError, "train one with `companion train style`")
    if not isinstance(blob, dict) or blob.get("format") != FORMAT or blob.get("kind") != kind:
        raise StyleModelError(f"{path}: not a {kind} file of the style-transfer system")
    return blob


def _restore(path: Path, blob: dict[str, Any], module: nn.Module) -> None:
    try:
        module.load_state_dict(blob["state_dict"])
    except Exception as exc:
        raise StyleModelError(f"{path}: weights do not match the stored config ({exc})"
                              ) from None
    module.eval()


def load_transfer(path: Path) -> tuple[StyleTransferModel, Vocab, DecodeConfig, dict]:
    """The transfer model, its vocabulary, decoding settings and the rest of the file."""
    blob = read_model_file(path, "style")
    try:
        vocab = Vocab(blob["vocab"])
        model = StyleTransferModel(len(vocab), ModelConfig(**blob["config"]))
        decode = DecodeConfig(**blob["decode"])
    except Exception as exc:
        raise StyleModelError(f"{path}: invalid stored config ({exc})") from None
    _restore(path, blob, model)
    return model, vocab, decode, blob


def load_classifier(path: Path) -> tuple[SentimentClassifier, Vocab, dict]:
    """The sentiment classifier, its vocabulary and the rest of the file."""
    blob = read_model_file(path, "classifier")
    try:
        vocab = Vocab(blob["vocab"])
        net = SentimentClassifier(len(vocab), ClassifierConfig(**blob["config"]))
    except Exception as exc:
        raise StyleModelError(f"{path}: invalid stored config ({exc})") from None
    _restore(path, blob, net)
    return net, vocab, blob


def load_lm(path: Path) -> tuple[LanguageModel, Vocab, dict]:
    """The fluency language model, its vocabulary and the rest of the file."""
    blob = read_model_file(path, "lm")
    try:
        vocab = Vocab(blob["vocab"])
        net = LanguageModel(len(vocab), LMConfig(**blob["config"]))
    except Exception as exc:
        raise StyleModelError(f"{path}: invalid stored config ({exc})") from None
    _restore(path, blob, net)
    return net, vocab, blob


