"""A word n-gram language model for the recogniser, estimated from the project's own lines
and written in the ARPA format that pocketsphinx reads.

Estimation is interpolated absolute discounting (Ney, Essen and Kneser, 1994): an n-gram
seen ``c`` times after the history ``h`` gets ``(c - D) / c(h)`` plus the mass taken from
the n-grams seen after ``h``, ``D * N1+(h .) / c(h)``, spread over the words by the next
lower order. That mass is exactly an ARPA back-off weight, so writing the interpolated
probabilities of the seen n-grams with those weights gives a back-off model with the same
distribution.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path

from core.checkpoint import atomic_write_bytes

START, END = "<s>", "</s>"
NO_PROB = -99.0   # the log10 probability ARPA files give the sentence start


def ngram_counts(sources: Iterable[tuple[float, Iterable[Sequence[str]]]], order: int,
                 min_count: float = 0.0) -> list[Counter]:
    """Weighted counts of the 1- to ``order``-grams of each source's sentences (padded with
    <s> and </s>), each source's counts times its weight (count merging, Bacchiani and
    Roark, 2003). N-grams longer than one word with a smaller total than ``min_count`` are
    dropped."""
    counts: list[Counter] = [Counter() for _ in range(order)]
    for weight, sentences in sources:
        for words in sentences:
            padded = (START, *words, END)
            for n in range(1, order + 1):
                for i in range(len(padded) - n + 1):
                    counts[n - 1][padded[i:i + n]] += weight
    for n in range(1, order):
        counts[n] = Counter({g: c for g, c in counts[n].items() if c >= min_count})
    return counts


@dataclass
class NGramModel:
    """Each order's n-grams with their probability, and the histories' back-off weights."""

    probs: list[dict[tuple[str, ...], float]]
    weights: list[dict[tuple[str, ...], float]]

    @classmethod
    def estimate(cls, counts: list[Counter], discount: float) -> NGramModel:
        """Interpolated absolute discounting with ``discount`` (0 < D < 1)."""
        unigrams = {g: c for g, c in counts[0].items() if g != (START,)}
        total = sum(unigrams.values())
        model = cls([{g: c / total for g, c in unigrams.items()}], [])
        model.probs[0][(START,)] = 0.0
        for grams in counts[1:]:
            seen: Counter = Counter()
            kinds: Counter = Counter()
            for gram, c in grams.items():
                seen[gram[:-1]] += c
                kinds[gram[:-1]] += 1
            weights = {h: discount * kinds[h] / seen[h] for h in seen}
            model.weights.append(weights)
            model.probs.append({gram: max(c - discount, 0.0) / seen[gram[:-1]]
                                + weights[gram[:-1]] * model.prob(gram[1:])
                                for gram, c in grams.items()})
        return model

    def prob(self, gram: tuple[str, ...]) -> float:
        """P(last word | the words before it), backing off through shorter histories."""
        n = len(gram)
        if gram in self.probs[n - 1]:
            return self.probs[n - 1][gram]
        if n == 1:
            return 0.0
        weight = self.weights[n - 2].get(gram[:-1], 1.0)
        return weight * self.prob(gram[1:])

    def arpa(self) -> str:
        """The model as an ARPA file's text (log10 values)."""
        order = len(self.probs)
        lines = ["\\data\\", *(f"ngram {n + 1}={len(p)}" for n, p in enumerate(self.probs)), ""]
        for n, probs in enumerate(self.probs):
            lines.append(f"\\{n + 1}-grams:")
            weights = self.weights[n] if n < order - 1 else {}
            for gram in sorted(probs):
                p = probs[gram]
                logp = NO_PROB if gram == (START,) else math.log10(p)
                row = f"{logp:.6f}\t{' '.join(gram)}"
                if n < order - 1:
                    row += f"\t{math.log10(weights.get(gram, 1.0)):.6f}"
                lines.append(row)
            lines.append("")
        lines.append("\\end\\")
        return "\n".join(lines) + "\n"

    def save(self, path: Path) -> None:
        """Write the ARPA file, whole or not at all."""
        atomic_write_bytes(path, self.arpa().encode())
