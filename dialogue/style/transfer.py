"""``StyleTransfer``: say a sentence in the robot's mood (positive or negative style).

Sentences are tokenised like the Yelp data (lower case, ``did n't``, punctuation apart) and
raw translations are in that tokenised form; what :meth:`StyleTransfer.translate` returns is
detokenised and capitalised like its source. Words outside the vocabulary become
``<unk>``; each ``<unk>`` the model writes is replaced by the source's unknown words in
order (dropped when none is left).

Confidence check (content preservation): the *content words* of a sentence are its words
with a letter that are neither stop words nor style markers (words one style uses at least
``style_ratio`` times as often as the other in training, saved with the model). A
translation is kept only when it contains at least ``min_content_overlap`` of the source's
content words (a source without content words always passes); otherwise the original
sentence is returned unchanged, so the robot never says something off-topic.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import torch

from app.core.torch_threads import torch_threads
from dialogue.style.config import DEFAULT_MODEL_DIR, STYLE_FILE
from dialogue.style.decode import transfer_ids
from dialogue.style.files import STOPWORDS, load_transfer
from dialogue.style.text import STYLES, detokenize, tokenize
from textnets.vocab import UNK, UNK_ID, Vocab

DEFAULT_STYLE_MODEL = DEFAULT_MODEL_DIR / STYLE_FILE
_HAS_LETTER = re.compile(r"[a-z]")


@dataclass(frozen=True)
class Translation:
    """One result: what to say, the raw model output and the confidence check's verdict."""

    text: str
    transferred: str
    content_overlap: float
    kept_original: bool


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

    def __init__(self, model: torch.nn.Module, vocab: Vocab, beam_size: int,
                 max_extra_words: int, disc_weight: float, min_content_overlap: float,
                 style_words: Sequence[str], meta: dict | None = None,
                 threads: int | None = 1) -> None:
        self.model, self.vocab = model.eval(), vocab
        self.threads = threads
        self.meta = dict(meta or {})
        self.beam_size, self.max_extra_words = beam_size, max_extra_words
        self.disc_weight, self.min_content_overlap = disc_weight, min_content_overlap
        self.style_words = frozenset(style_words)

    @classmethod
    def load(cls, path: str | Path = DEFAULT_STYLE_MODEL, beam_size: int | None = None
             ) -> StyleTransfer:
        """Load ``style.pt``; a missing or corrupt file raises ``StyleModelError``."""
        model, vocab, decode, blob = load_transfer(Path(path))
        return cls(model, vocab, beam_size or decode.beam_size, decode.max_extra_words,
                   decode.disc_weight, decode.min_content_overlap,
                   [str(w) for w in blob.get("style_words", [])], blob.get("meta"))

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
        todo = [i for i, t in enumerate(tokens) if t]
        with torch_threads(self.threads):
            outputs = transfer_ids(self.model, [self.vocab.encode(tokens[i]) for i in todo],
                                   [1 - target] * len(todo), self.beam_size,
                                   self.max_extra_words, self.disc_weight)
        results = [Translation(s, s, 1.0, True) for s in sentences]
        for i, out in zip(todo, outputs, strict=True):
            words = replace_unknown([self.vocab.itos[j] if j != UNK_ID else UNK for j in out],
                                    tokens[i], self.vocab)
            overlap = self.content_overlap(tokens[i], words)
            keep = not words or overlap < self.min_content_overlap
            text = " ".join(words)
            said = sentences[i] if keep else readable(words, sentences[i])
            results[i] = Translation(said, text, overlap, keep)
        return results

    def translate(self, sentences: Sequence[str], to: str) -> list[str]:
        """Each sentence said in the ``to`` style ("positive" or "negative").

        A translation that loses the content (module docstring) is replaced by the original.
        """
        return [t.text for t in self.translate_detailed(sentences, to)]
