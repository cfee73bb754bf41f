"""The one vocabulary of the project's text networks: word <-> id, with the four special
tokens first (``<pad> <bos> <eos> <unk>``). Each model keeps its own tokenisation rules
(dialogue/chat/text.py, dialogue/style/text.py); the vocabulary only maps their tokens."""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterable, Sequence

PAD, BOS, EOS, UNK = "<pad>", "<bos>", "<eos>", "<unk>"
SPECIALS = (PAD, BOS, EOS, UNK)
PAD_ID, BOS_ID, EOS_ID, UNK_ID = range(4)


class Vocab:
    """Word <-> id mapping; ids 0-3 are ``<pad> <bos> <eos> <unk>``."""

    def __init__(self, words: Sequence[str]) -> None:
        self.itos = list(words)
        if tuple(self.itos[:4]) != SPECIALS:
            raise ValueError("a vocabulary starts with <pad> <bos> <eos> <unk>")
        self.stoi = {w: i for i, w in enumerate(self.itos)}

    @classmethod
    def build(cls, sentences: Iterable[Sequence[str]], min_count: int) -> Vocab:
        """Words seen at least ``min_count`` times, most frequent first (ties alphabetical)."""
        counts = Counter(w for s in sentences for w in s)
        words = sorted((w for w, c in counts.items() if c >= min_count and w not in SPECIALS),
                       key=lambda w: (-counts[w], w))
        return cls([*SPECIALS, *words])

    def __len__(self) -> int:
        return len(self.itos)

    def encode(self, words: Sequence[str]) -> list[int]:
        """Ids of ``words``; unknown words become ``<unk>``."""
        return [self.stoi.get(w, UNK_ID) for w in words]

    def decode(self, ids: Iterable[int], skip_unknown: bool = False) -> list[str]:
        """Words up to the first ``<eos>``, without ``<pad>`` and ``<bos>``; ``<unk>`` is kept
        (style transfer fills it with the source's unknown words) unless ``skip_unknown``
        (chit-chat never says it)."""
        out = []
        for i in ids:
            if i == EOS_ID:
                break
            if i not in (PAD_ID, BOS_ID) and not (skip_unknown and i == UNK_ID):
                out.append(self.itos[i])
        return out
