"""``StyleTransfer``: say a sentence in the robot's mood (positive or negative style).

Sentences are tokenised like the Yelp data (lower case, ``did n't``, punctuation apart) and
raw translations are in that tokenised form; what :meth:`StyleTransfer.translate` returns is
detokenised and capitalised like its source. Words outside the vocabulary become
``<unk>``; each ``<unk>`` the model writes is replaced by the source's unknown words in
order (dropped when none is left).

Checks before decoding: a sentence longer than ``decode.max_words`` words, or one with fewer
than ``decode.min_known_share`` of its words (those with a letter) in the vocabulary (text in
another language, say), is not decoded at all.

Confidence check (content preservation): the *content words* of a sentence are its words
with a letter that are neither stop words nor style markers (words one style uses at least
``style_ratio`` times as often as the other in training, saved with the model). A
translation is kept only when it contains at least ``min_content_overlap`` of the source's
content words (a source without content words always passes).

Whenever a check fails the original sentence is returned unchanged, so the robot never says
something off-topic, and :meth:`StyleTransfer.translate_detailed` says why.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import torch

from core.torch_threads import torch_threads
from dialogue.style.config import DEFAULT_MODEL_DIR, STYLE_FILE, DecodeConfig
from dialogue.style.decode import transfer_ids
from dialogue.style.files import STOPWORDS, load_transfer
from dialogue.style.text import STYLES, detokenize, tokenize
from textnets.vocab import UNK, UNK_ID, Vocab

DEFAULT_STYLE_MODEL = DEFAULT_MODEL_DIR / STYLE_FILE
_HAS_LETTER = re.compile(r"[a-z]")


@dataclass(frozen=True)
class Translation:
    """One result: what to say, the raw model output ("" when the sentence was not decoded),
    the share of the source's content words in it (0 when not decoded), the share of the
    source's words the model knows and, when the original is said instead, why."""

    text: str
    transferred: str
    content_overlap: float
    known_share: float
    reason: str | None = None

    @property
    def kept_original(self) -> bool:
        """Whether a check failed and ``text`` is the source sentence unchanged."""
        return self.reason is not None


def replace_unknown(output: Sequence[str], source: Sequence[str], vocab: Vocab) -> list[str]:
    """Fill the output's ``<unk>`` with the source's out-of-vocabulary words, in order."""
    pending = [w for w in source if w not in vocab.stoi]
    out = []
    for w in output:
        if w == UNK:
            if pending:
                out.append(pending.pop(0))
        else:
            out.append(w)
    return out


def readable(words: Sequence[str], source: str) -> str:
    """The tokens as a sentence to say, capitalised like the source."""
    text = detokenize(words)
    upper = source.lstrip()[:1].isupper()
    return text[:1].upper() + text[1:] if upper else text


class StyleTransfer:
    """``translate(sentences, to)`` with the cross-aligned model of thesis §3.3.

    Decoding runs with ``threads`` torch threads (default 1): the tensors of a few sentences
    are small, and more threads only add waiting, badly so on a busy machine.
    """

    def __init__(self, model: torch.nn.Module, vocab: Vocab, decode: DecodeConfig,
                 style_words: Sequence[str], meta: dict | None = None,
                 threads: int | None = 1) -> None:
        self.model, self.vocab, self.decode = model.eval(), vocab, decode
        self.threads = threads
        self.meta = dict(meta or {})
        self.beam_size, self.max_extra_words = decode.beam_size, decode.max_extra_words
        self.disc_weight = decode.disc_weight
        self.style_words = frozenset(style_words)

    @classmethod
    def load(cls, path: str | Path = DEFAULT_STYLE_MODEL, beam_size: int | None = None
             ) -> StyleTransfer:
        """Load ``style.pt``; a missing or corrupt file raises ``StyleModelError``."""
        model, vocab, decode, blob = load_transfer(Path(path))
        if beam_size is not None:
            decode = decode.model_copy(update={"beam_size": beam_size})
        return cls(model, vocab, decode, [str(w) for w in blob.get("style_words", [])],
                   blob.get("meta"))

    def known_share(self, words: Sequence[str]) -> float:
        """Share of the words with a letter that are in the vocabulary (1.0 without any)."""
        lettered = [w for w in words if _HAS_LETTER.search(w)]
        return sum(w in self.vocab.stoi for w in lettered) / len(lettered) if lettered else 1.0

    def refusal(self, words: Sequence[str]) -> str | None:
        """Why a tokenised sentence is not decoded at all, or None when it is."""
        if not words:
            return "it has no words"
        if len(words) > self.decode.max_words:
            return (f"it has {len(words)} words, more than the model's limit of "
                    f"{self.decode.max_words}")
        known = self.known_share(words)
        if known < self.decode.min_known_share:
            return (f"only {known:.0%} of its words are known to the model, fewer than "
                    f"{self.decode.min_known_share:.0%} (is it English?)")
        return None

    def content_words(self, words: Sequence[str]) -> set[str]:
        """Words that carry content: with a letter, not stop words, not style markers."""
        return {w for w in words if _HAS_LETTER.search(w) and w not in STOPWORDS
                and w not in self.style_words}

    def content_overlap(self, source: Sequence[str], output: Sequence[str]) -> float:
        """Share of the source's content words found in the output (1.0 when it has none)."""
        content = self.content_words(source)
        if not content:
            return 1.0
        return len(content & set(output)) / len(content)

    def translate_detailed(self, sentences: Sequence[str], to: str) -> list[Translation]:
        """Translate and apply the confidence check, keeping every intermediate."""
        if to not in STYLES:
            raise ValueError(f"to must be one of {STYLES}, got {to!r}")
        target = STYLES.index(to)
        tokens = [tokenize(s) for s in sentences]
        results = [Translation(s, "", 0.0, self.known_share(t), self.refusal(t))
                   for s, t in zip(sentences, tokens, strict=True)]
        todo = [i for i, r in enumerate(results) if r.reason is None]
        with torch_threads(self.threads):
            outputs = transfer_ids(self.model, [self.vocab.encode(tokens[i]) for i in todo],
                                   [1 - target] * len(todo), self.beam_size,
                                   self.max_extra_words, self.disc_weight)
        for i, out in zip(todo, outputs, strict=True):
            words = replace_unknown([self.vocab.itos[j] if j != UNK_ID else UNK for j in out],
                                    tokens[i], self.vocab)
            overlap = self.content_overlap(tokens[i], words)
            why = self._lost(words, overlap)
            said = sentences[i] if why else readable(words, sentences[i])
            results[i] = Translation(said, " ".join(words), overlap, results[i].known_share,
                                     why)
        return results

    def _lost(self, words: Sequence[str], overlap: float) -> str | None:
        """Why a decoded translation fails the confidence check, or None when it passes."""
        if not words:
            return "the model wrote nothing"
        if overlap < self.decode.min_content_overlap:
            return (f"the translation kept {overlap:.0%} of its content words, fewer than "
                    f"{self.decode.min_content_overlap:.0%}")
        return None

    def translate(self, sentences: Sequence[str], to: str) -> list[str]:
        """Each sentence said in the ``to`` style ("positive" or "negative").

        A sentence that fails a check (module docstring) is returned unchanged.
        """
        return [t.text for t in self.translate_detailed(sentences, to)]
