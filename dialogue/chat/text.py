"""How the chit-chat model sees text: lower-case PTB-style tokens (``do n't``, ``i 'm``,
punctuation apart, the form Papaya already has), ``_slot_`` placeholders as ``<unk>``, and
readable sentences back."""

from __future__ import annotations

import re
from collections.abc import Sequence

from textnets.vocab import UNK

SLOT = re.compile(r"^_[a-z0-9]+_$")
_NT = re.compile(r"(\w)n't\b")
_CLITIC = re.compile(r"(\w)'(s|m|re|ve|ll|d)\b")
_TOKEN = re.compile(r"<unk>|n't\b|'(?:s|m|re|ve|ll|d)\b|\w+(?:[-.]\w+)*|[^\w\s]")
_QUOTES = str.maketrans({"\u2019": "'", "\u2018": "'", "\u201c": '"', "\u201d": '"'})


_GLUE_LEFT = {".", ",", "!", "?", ";", ":", ")", "%", "n't", "'s", "'m", "'re", "'ve", "'ll",
              "'d"}


Pair = tuple[tuple[str, ...], tuple[str, ...]]


def tokenize(text: str) -> list[str]:
    """Lower-case PTB-style tokens; ``_slot_`` placeholders become ``<unk>``."""
    s = text.translate(_QUOTES).replace("``", '"').replace("''", '"').lower()
    s = _CLITIC.sub(r"\1 '\2", _NT.sub(r"\1 n't", s))
    return [UNK if SLOT.match(t) else t for t in _TOKEN.findall(s)]


def pair_tokens(line: str, reply: str) -> Pair:
    """An (input, reply) text pair as tokens: how training and the retrieval pool alike
    normalise a pair read from the data."""
    return tuple(tokenize(line)), tuple(tokenize(reply))


def detokenize(tokens: Sequence[str]) -> str:
    """Readable text from tokens: punctuation and clitics glued, sentences capitalised."""
    out, cap = "", True
    for t in tokens:
        word = t.upper() if t == "i" else t
        if cap and word[:1].isalpha():
            word, cap = word[:1].upper() + word[1:], False
        if not out or out.endswith(("(", "$")) or t in _GLUE_LEFT:
            out += word
        else:
            out += " " + word
        cap = cap or t in (".", "!", "?")
    return out
