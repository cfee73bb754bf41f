"""A small word-bigram language model (interpolated Kneser-Ney) that knows conversation.

The mood gate compares the perplexity of a styled reply with that of the unstyled one, so the
language model has to know how the robot talks, not only how Yelp reviewers write. A bigram
model is enough to notice "fine , disappointed you" next to "fine , thank you", trains in
seconds and is stored in a few megabytes as plain arrays (``numpy.load`` without pickle).

Probability of word ``w`` after ``v`` (``D`` the discount, ``c`` counts, ``N1+`` the number
of distinct neighbours)::

    p(w | v) = max(c(v, w) - D, 0) / c(v) + D * N1+(v .) / c(v) * p_cont(w)
    p_cont(w) = (N1+(. w) + 1) / (N1+(. .) + V - 1)      (0 for <s>)

A history never seen uses ``p_cont`` alone; words outside the vocabulary are ``<unk>``.
Bigrams seen once are not stored (``keep_min``), but they still count in ``c(v)`` and in
the ``N1+`` figures, so the model keeps their probability mass for the unseen.
"""

from __future__ import annotations

import itertools
import math
from collections import Counter
from collections.abc import Iterable, Sequence
from pathlib import Path

import numpy as np

from core.errors import UserError

BOS, EOS, UNK_WORD = "<s>", "</s>", "<unk>"
FORMAT = "companion-bigram-1"


class NgramModelError(UserError):
    """The bigram model file is missing, unreadable or inconsistent."""


class BigramLM:
    """Kneser-Ney bigram model over a fixed vocabulary (see the module docstring)."""

    def __init__(self, words: Sequence[str], keys: np.ndarray, counts: np.ndarray,
                 history: np.ndarray, followers: np.ndarray, continuation: np.ndarray,
                 discount: float) -> None:
        self.words = list(words)
        self.stoi = {w: i for i, w in enumerate(self.words)}
        self.keys, self.counts = keys.astype(np.int64), counts.astype(np.float64)
        self.history, self.followers = history.astype(np.float64), followers.astype(np.float64)
        self.continuation = continuation.astype(np.int32)
        self.p_cont = (self.continuation + 1.0) / (self.continuation.sum() + len(self.words) - 1)
        self.p_cont[0] = 0.0   # <s> is never predicted
        self.discount = discount

    @classmethod
    def train(cls, sentences: Iterable[Sequence[str]], min_count: int = 2,
              discount: float = 0.75, keep_min: int = 2) -> BigramLM:
        """Count the bigrams of tokenised ``sentences``; words seen fewer than ``min_count``
        times become ``<unk>``."""
        sentences = [list(s) for s in sentences]
        freq = Counter(w for s in sentences for w in s)
        words = [BOS, EOS, UNK_WORD, *sorted(w for w, n in freq.items() if n >= min_count)]
        stoi = {w: i for i, w in enumerate(words)}
        pairs: Counter[tuple[int, int]] = Counter()
        for s in sentences:
            ids = [0, *(stoi.get(w, 2) for w in s), 1]
            pairs.update(itertools.pairwise(ids))
        v = len(words)
        history, followers, continuation = np.zeros(v), np.zeros(v), np.zeros(v)
        for (a, b), n in pairs.items():
            history[a] += n
            followers[a] += 1
            continuation[b] += 1
        kept = sorted((a * v + b, n) for (a, b), n in pairs.items() if n >= keep_min)
        keys = np.array([k for k, _ in kept], dtype=np.int64)
        counts = np.array([n for _, n in kept], dtype=np.int32)
        return cls(words, keys, counts, history, followers, continuation, discount)

    def ids(self, words: Sequence[str]) -> list[int]:
        """``<s>``, the words' ids (``<unk>`` for unknown ones) and ``</s>``."""
        return [0, *(self.stoi.get(w, 2) for w in words), 1]

    def seen(self, prev: str, word: str) -> int:
        """How often the bigram ``prev word`` was counted (0 for bigrams seen fewer than the
        ``keep_min`` times kept, or with an unknown word); ``<s>``/``</s>`` mark the ends."""
        a, b = self.stoi.get(prev, 2), self.stoi.get(word, 2)
        if 2 in (a, b):
            return 0
        key = a * len(self.words) + b
        at = int(np.searchsorted(self.keys, key))
        return int(self.counts[at]) if at < len(self.keys) and self.keys[at] == key else 0

    def prob(self, prev: int, word: int) -> float:
        """``p(word | prev)`` for two ids (module docstring)."""
        cont = float(self.p_cont[word])
        if self.history[prev] == 0:
            return cont
        key = prev * len(self.words) + word
        at = int(np.searchsorted(self.keys, key))
        seen = self.counts[at] if at < len(self.keys) and self.keys[at] == key else 0.0
        return (max(seen - self.discount, 0.0)
                + self.discount * self.followers[prev] * cont) / self.history[prev]

    def logprob(self, words: Sequence[str]) -> float:
        """Natural-log probability of the sentence, ``</s>`` included."""
        return sum(math.log(self.prob(a, b)) for a, b in itertools.pairwise(self.ids(words)))

    def perplexity(self, words: Sequence[str]) -> float:
        """Per-word perplexity of one tokenised sentence (``</s>`` counted as a word)."""
        return math.exp(-self.logprob(words) / (len(words) + 1))

    def save(self, path: Path) -> None:
        """Write the arrays to ``path`` (an ``.npz`` file, compressed, no pickled objects)."""
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_name(path.name + ".tmp.npz")
        np.savez_compressed(tmp, format=np.array(FORMAT), words=np.array(self.words),
                            keys=self.keys, counts=self.counts.astype(np.int32),
                            history=self.history.astype(np.int64),
                            followers=self.followers.astype(np.int32),
                            continuation=self.continuation, discount=np.array(self.discount))
        tmp.replace(path)

    @classmethod
    def load(cls, path: str | Path) -> BigramLM:
        """Read a file written by :meth:`save`; a bad one raises :class:`NgramModelError`."""
        path = Path(path)
        try:
            with np.load(path, allow_pickle=False) as z:
                if str(z["format"]) != FORMAT:
                    raise ValueError("not a bigram model file")
                lm = cls([str(w) for w in z["words"]], z["keys"], z["counts"], z["history"],
                         z["followers"], z["continuation"], float(z["discount"]))
        except (OSError, ValueError, KeyError) as exc:
            raise NgramModelError(f"{path}: cannot read the bigram language model ({exc}); "
                                  "train one with `companion train mood-lm`") from None
        return lm
