"""``companion train acts``: the act and care heads on the sentence embeddings of the
project's labelled lines (``training.training_file``) and, as :data:`QUESTION`, of the
intent router's training questions.

The features are the word and character TF-IDF of the lines (the vectorizers fitted here)
beside their sentence embeddings (:func:`dialogue.acts.model.features`). Each head is
scikit-learn's multinomial logistic regression with balanced class weights and its ``c``;
5-fold cross-validation on the training lines (never the development or test ones) gives
the accuracy recorded beside the heads, the figure that chose each ``c``.
"""

from __future__ import annotations

import hashlib
import json
from pathlib import Path
from typing import Any

import numpy as np
import scipy.sparse as sp

from core.checkpoint import atomic_write
from core.paths import from_root
from dialogue.acts.config import QUESTION, ActsConfig
from dialogue.acts.encoder import SentenceEncoder
from dialogue.acts.model import HEADS_FILE, TFIDF, features, load_act_lines, vectorizer
from dialogue.intent import CHITCHAT, TRAIN_FILE, load_utterances

FOLDS = 5


def training_set(cfg: ActsConfig) -> tuple[list[str], np.ndarray, np.ndarray]:
    """The lines, their acts and their care signals (the router's questions last)."""
    rows = load_act_lines(from_root(cfg.training.training_file))
    questions = [t for label, t in load_utterances(TRAIN_FILE) if label != CHITCHAT]
    texts = [t for _, _, t in rows] + questions
    acts = np.array([a for a, _, _ in rows] + [QUESTION] * len(questions))
    care = np.array([c for _, c, _ in rows] + ["none"] * len(questions))
    return texts, acts, care


def fit(texts: list[str], embedded: np.ndarray, y: np.ndarray, c: float,
        cfg: ActsConfig) -> tuple[list[Any], Any]:
    """The vectorizers fitted on ``texts`` and one head on their features."""
    from sklearn.linear_model import LogisticRegression

    vectorizers = [vectorizer(name).fit(texts) for name in TFIDF]
    head = LogisticRegression(C=c, max_iter=cfg.training.max_iter, class_weight="balanced")
    return vectorizers, head.fit(features(vectorizers, texts, embedded), y)


def cross_validated(texts: list[str], embedded: np.ndarray, y: np.ndarray, c: float,
                    cfg: ActsConfig, seed: int = 0) -> np.ndarray:
    """The labels ``FOLDS``-fold cross-validation gives each line."""
    from sklearn.model_selection import StratifiedKFold

    out = np.empty(len(y), dtype=y.dtype)
    split = StratifiedKFold(FOLDS, shuffle=True, random_state=seed).split(embedded, y)
    for train, test in split:
        vectorizers, head = fit([texts[i] for i in train], embedded[train], y[train], c, cfg)
        out[test] = head.predict(features(vectorizers, [texts[i] for i in test],
                                          embedded[test]))
    return out


def save_heads(path: Path, vectorizers: list[Any], heads: dict[str, Any],
               meta: dict[str, Any]) -> None:
    """The vectorizers' terms and weights and the heads, as plain arrays (strings, no
    pickles), and ``meta`` as JSON text."""
    arrays = {"meta": np.array(json.dumps(meta, sort_keys=True))}
    for name, v in zip(TFIDF, vectorizers, strict=True):
        arrays |= {f"{name}_terms": np.array(sorted(v.vocabulary_, key=v.vocabulary_.get)),
                   f"{name}_idf": v.idf_.astype(np.float32)}
    for name, head in heads.items():
        arrays |= {f"{name}_labels": np.array([str(c) for c in head.classes_]),
                   f"{name}_coef": sp.csr_matrix(head.coef_.T).toarray().astype(np.float32),
                   f"{name}_intercept": head.intercept_.astype(np.float32)}
    atomic_write(path, lambda fh: np.savez(fh, **arrays))


def train_heads(cfg: ActsConfig, out: Path) -> dict[str, Any]:
    """Fit the vectorizers and both heads with the encoder in ``out``, save them there;
    their figures, with the cross-validated care alerts (recall and false alerts)."""
    t = cfg.training
    texts, acts, care = training_set(cfg)
    x = SentenceEncoder(out).embed(texts)
    lines = len(texts) - int((acts == QUESTION).sum())
    cv_acts = cross_validated(texts, x, acts, t.c_act, cfg)
    cv_care = cross_validated(texts, x, care, t.c_care, cfg)
    told, raised = care != "none", cv_care != "none"
    meta = {"training_file": str(t.training_file), "lines": lines,
            "questions": len(texts) - lines, "c_act": t.c_act, "c_care": t.c_care,
            "max_iter": t.max_iter, "class_weight": "balanced", "tfidf": TFIDF,
            "sha256": hashlib.sha256("\n".join(texts).encode()).hexdigest(),
            "cv_act_accuracy": float((cv_acts == acts).mean()),
            "cv_care_accuracy": float((cv_care == care).mean()),
            "cv_care_recall": float(raised[told].mean()),
            "cv_false_alerts": float(raised[~told].mean())}
    vectorizers, act_head = fit(texts, x, acts, t.c_act, cfg)
    _, care_head = fit(texts, x, care, t.c_care, cfg)   # the same vectorizers: same texts
    save_heads(out / HEADS_FILE, vectorizers, {"act": act_head, "care": care_head}, meta)
    return meta
