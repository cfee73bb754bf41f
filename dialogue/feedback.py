"""Spoken feedback: whether a line said to the robot praises (+1) or scolds (-1) what it
does, or is neither (0): the thesis's external reward, heard.

The same kind of model as the intent router (:class:`dialogue.intent.TextModel`), trained at
start-up on the project's own labelled lines (``dialogue/data/feedback_train.tsv``), with
every utterance of the intent router's training file as a "neither" example: questions and
chit-chat are not feedback. A line counts as feedback only when the model is at least
``threshold`` sure, so an unclear line is never taken for a scolding.
"""

from __future__ import annotations

from functools import cache

from dialogue.intent import DATA, TRAIN_FILE, TextModel, load_utterances
from dialogue.intent import LABELS as INTENTS
from mind.preferences.config import load_feedback_config

FEEDBACK_TRAIN = DATA / "feedback_train.tsv"
FEEDBACK_HELDOUT = DATA / "feedback_heldout.tsv"
KINDS = ("praise", "scold", "none")
VALUE = {"praise": 1, "scold": -1, "none": 0}


def training_lines() -> list[tuple[str, str]]:
    """The feedback lines, and every intent-training utterance as ``none``."""
    return [*load_utterances(FEEDBACK_TRAIN, KINDS),
            *(("none", text) for _, text in load_utterances(TRAIN_FILE, INTENTS))]


class FeedbackClassifier:
    """``value(text)``: +1 praise, -1 scolding, 0 neither."""

    def __init__(self, examples: list[tuple[str, str]] | None = None,
                 threshold: float | None = None) -> None:
        """``threshold`` None: ``spoken.threshold`` of ``config/feedback.yaml``."""
        self.model = TextModel(examples if examples is not None else training_lines())
        self.threshold = (load_feedback_config().spoken.threshold if threshold is None
                          else threshold)

    @classmethod
    @cache
    def default(cls) -> FeedbackClassifier:
        """The classifier trained on the shipped lines (built once per process)."""
        return cls()

    def kind(self, text: str) -> str:
        """``praise``, ``scold`` or ``none`` for ``text``."""
        probs = self.model.probabilities(text)
        best = int(probs.argmax())
        label = self.model.labels[best]
        return label if probs[best] >= self.threshold else "none"

    def value(self, text: str) -> int:
        """The external reward ``text`` gives: +1, -1 or 0."""
        return VALUE[self.kind(text)]


def evaluate_feedback(classifier: FeedbackClassifier | None = None) -> dict:
    """Accuracy on the held-out lines, per kind, and the misses."""
    clf = classifier or FeedbackClassifier.default()
    pairs = load_utterances(FEEDBACK_HELDOUT, KINDS)
    misses = [{"text": t, "expected": k, "got": clf.kind(t)} for k, t in pairs
              if clf.kind(t) != k]
    total = {k: sum(label == k for label, _ in pairs) for k in KINDS}
    per = {k: 1 - sum(m["expected"] == k for m in misses) / max(1, total[k]) for k in KINDS}
    return {"accuracy": 1 - len(misses) / len(pairs), "per_kind": per, "misses": misses}
