"""The conversation-act model: what a line shares (an act of :data:`ACTS`, or a question for
the QA bot) and whether it is a care signal (:data:`CARE`).

Two logistic-regression heads over the line's features: TF-IDF of its word uni- and
bigrams and of its character 2-4-grams (which see "tablets" and "dizzy"), beside its
sentence embedding (:class:`dialogue.acts.encoder.SentenceEncoder`, which sees what a line
means however it is put), trained by ``companion train acts`` on the project's own labelled
lines (``dialogue/data/acts_train.tsv``) and, as questions, the intent router's training
questions (:mod:`dialogue.acts.training.train`). The held-out lines of
``dialogue/data/conversation_dev.tsv`` and ``conversation_test.tsv`` were written separately
and are never trained on.
The heads are a plain ``.npz`` of arrays, read without pickles.
"""

from __future__ import annotations

import zipfile
from dataclasses import dataclass
from functools import cache
from pathlib import Path
from typing import Any

import numpy as np
import scipy.sparse as sp

from core.errors import UserError
from core.files import read_text
from dialogue.acts.config import ACTS, CARE, QUESTION, ActsConfig, load_acts_config
from dialogue.acts.encoder import SentenceEncoder
from dialogue.qa.base import DialogueError

HEADS_FILE = "acts.npz"
TFIDF = {"words": {"ngram_range": (1, 2)},                       # the vectorizers' settings
         "chars": {"analyzer": "char_wb", "ngram_range": (2, 4)}}


def vectorizer(name: str, vocabulary: dict[str, int] | None = None) -> Any:
    """scikit-learn's TF-IDF vectorizer ``name`` of :data:`TFIDF` (sublinear counts), with a
    fixed ``vocabulary`` when given."""
    from sklearn.feature_extraction.text import TfidfVectorizer

    return TfidfVectorizer(sublinear_tf=True, vocabulary=vocabulary, **TFIDF[name])


def features(vectorizers: list[Any], texts: list[str], embedded: np.ndarray) -> sp.csr_matrix:
    """The rows of features of ``texts``: each vectorizer's TF-IDF, then the embeddings."""
    return sp.hstack([*(v.transform(texts) for v in vectorizers),
                      sp.csr_matrix(embedded)]).tocsr()


@dataclass(frozen=True)
class Reading:
    """What the act model read in a line: the act (or :data:`QUESTION`) and the care signal
    ("none" when there is none), each with its probability."""

    act: str
    act_confidence: float
    care: str
    care_confidence: float
    acts: dict[str, float]     # the probability of every act (and of a question)


def load_act_lines(path: str | Path) -> list[tuple[str, str, str]]:
    """``(act, care, line)`` from an ``act<TAB>care<TAB>line`` file (``#`` comments)."""
    rows = []
    for n, line in enumerate(read_text(path).splitlines(), 1):
        if not line.strip() or line.startswith("#"):
            continue
        parts = line.split("\t")
        if len(parts) != 3 or parts[0] not in ACTS or parts[1] not in CARE or not parts[2].strip():
            raise DialogueError(f"{path}:{n}: expected '<act><TAB><care><TAB><line>' with an "
                                f"act in {', '.join(ACTS)} and care in {', '.join(CARE)}")
        rows.append((parts[0], parts[1], parts[2].strip()))
    return rows


@dataclass(frozen=True)
class Head:
    """A softmax layer: ``labels``, weights ``coef`` (embedding x labels), ``intercept``."""

    labels: tuple[str, ...]
    coef: np.ndarray
    intercept: np.ndarray

    def probabilities(self, x: sp.csr_matrix) -> np.ndarray:
        """The probability of each label for each row of features ``x``."""
        z = np.asarray(x @ self.coef) + self.intercept
        z = np.exp(z - z.max(axis=-1, keepdims=True))
        return z / z.sum(axis=-1, keepdims=True)


def load_heads(path: Path) -> tuple[list[Any], Head, Head]:
    """The vectorizers and the act and care heads saved by
    :func:`dialogue.acts.training.train.save_heads` (plain arrays: no pickles)."""
    try:
        with np.load(path, allow_pickle=False) as f:
            vectorizers = []
            for name in TFIDF:
                terms = [str(t) for t in f[f"{name}_terms"]]
                v = vectorizer(name, {t: i for i, t in enumerate(terms)})
                v.idf_ = f[f"{name}_idf"]
                vectorizers.append(v)
            act, care = (Head(tuple(str(s) for s in f[f"{k}_labels"]), f[f"{k}_coef"],
                              f[f"{k}_intercept"]) for k in ("act", "care"))
            return vectorizers, act, care
    except (OSError, KeyError, ValueError, zipfile.BadZipFile) as exc:
        raise UserError(f"{path}: not an act model ({exc}); run `companion train acts`") from None


class ActModel:
    """Reads the act and the care signal of a line; see :meth:`read`."""

    def __init__(self, encoder: SentenceEncoder, vectorizers: list[Any], acts: Head,
                 care: Head, cfg: ActsConfig) -> None:
        self.encoder, self.vectorizers, self.cfg = encoder, vectorizers, cfg
        self.acts, self.care = acts, care

    @classmethod
    def load(cls, cfg: ActsConfig) -> ActModel:
        """The encoder, vectorizers and heads of ``cfg.model_dir``."""
        folder = cfg.resolved_model_dir()
        vectorizers, acts, care = load_heads(folder / HEADS_FILE)
        return cls(SentenceEncoder(folder), vectorizers, acts, care, cfg)

    @classmethod
    @cache
    def default(cls) -> ActModel:
        """The model of the packaged config (loaded once per process)."""
        return cls.load(load_acts_config())

    def read(self, text: str) -> Reading:
        """The act and care signal of ``text``, each the most likely label."""
        x = features(self.vectorizers, [text], self.encoder.embed([text]))
        acts, care = self.acts.probabilities(x)[0], self.care.probabilities(x)[0]
        a, c = int(acts.argmax()), int(care.argmax())
        return Reading(self.acts.labels[a], float(acts[a]), self.care.labels[c], float(care[c]),
                       dict(zip(self.acts.labels, map(float, acts), strict=True)))

    def alert(self, reading: Reading) -> str | None:
        """The care signal to raise for ``reading``: None for none, an unsure one, or one
        whose line the act head is surer is a plain question ("what time is it?")."""
        sure = reading.care_confidence >= self.cfg.classifier.care_min_confidence
        asked = reading.act == QUESTION and reading.act_confidence > reading.care_confidence
        return reading.care if sure and not asked and reading.care in self.cfg.care.alert \
            else None
