"""How the style-transfer model sees text: the Yelp files' tokenisation (lower case, PTB-style
clitics such as ``did n't``, punctuation apart, numbers as ``_num_``) and back."""

from __future__ import annotations

import re
from collections.abc import Sequence

STYLES = ("negative", "positive")
NUMBER = "_num_"
_PUNCT = re.compile(r"([.,!?;:()\"&])")
_CLITIC = re.compile(r"(\w)(n't|'s|'re|'ve|'m|'ll|'d)\b")
_NUMBER = re.compile(r"^\d+([.,:]\d+)*$")
_SENTENCE_END = re.compile(r"(?<=[.!?])\s+")


def _split(text: str) -> list[str]:
    """Lower-cased tokens with clitics and punctuation apart, numbers still as written."""
    text = text.lower().replace("\u2019", "'")
    text = _CLITIC.sub(r"\1 \2", text)
    return _PUNCT.sub(r" \1 ", text).split()


def tokenize(text: str) -> list[str]:
    """Lower-case and split free text the way the Yelp files are: ``didn't`` -> ``did n't``."""
    return [NUMBER if _NUMBER.match(w) else w for w in _split(text)]


def numbers(text: str) -> list[str]:
    """The numbers of free text as written, in order: what its ``_num_`` tokens stand for."""
    return [w for w in _split(text) if _NUMBER.match(w)]


def detokenize(words: Sequence[str]) -> str:
    """A readable sentence from tokens: ``it 's good !`` -> ``it's good!``."""
    text = " ".join(words)
    text = re.sub(r" (n't|'s|'re|'ve|'m|'ll|'d)\b", r"\1", text)
    return re.sub(r" ([.,!?;:)])", r"\1", text).replace("( ", "(")


def split_sentences(text: str) -> list[str]:
    """The sentences of a line of free text: split after ``.``, ``!`` or ``?`` and a space."""
    return [s for s in _SENTENCE_END.split(text.strip()) if s]
