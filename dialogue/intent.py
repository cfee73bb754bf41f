"""Intent routing: which QA category (thesis Table 3.4) an utterance asks for, or chit-chat.

The thesis let the person choose on the tablet and then told the QA categories apart by
cue words (zeta). Here a small model does it: logistic regression over TF-IDF features of
word uni- and bigrams (with known places, topics and songs replaced by placeholder words,
so "what is a koala" and "what is jazz" look alike) and of character 2-4-grams, trained at
start-up (well under a second) on the project's own utterances in
``dialogue/data/intent_train.tsv``. Cue words add a fixed bonus to their category's
probability. An explicit mode overrides the model, like the tablet buttons.
"""

from __future__ import annotations

import re
import time
from collections import Counter
from dataclasses import dataclass
from functools import cache
from pathlib import Path

import numpy as np

from core.files import read_text
from dialogue.qa import CATEGORIES
from dialogue.qa.base import DialogueError
from dialogue.qa.knowledge import KnowledgeBase
from dialogue.qa.music import shipped_songs
from dialogue.qa.places import COMMON, TIME_WORDS, known_place
from dialogue.qa.text import STOPWORDS, ngrams, normalise

DATA = Path(__file__).resolve().parent / "data"
TRAIN_FILE = DATA / "intent_train.tsv"
HELDOUT_FILE = DATA / "intent_heldout.tsv"
CHITCHAT = "chitchat"
LABELS = (*CATEGORIES, CHITCHAT)
MODES = ("auto", "qa", CHITCHAT, *CATEGORIES)
CUE_BONUS = 0.4
PLACE_PREPOSITIONS = frozenset({"in", "for", "at", "to", "near"})
CUES = {  # the thesis's zeta: words that point at one category
    "time": r"\bwhat time\b|\bthe time\b|\btime is it\b|\blocal time\b|\bo ?clock\b|\bhour\b"
            r"|\bwhat day is it\b|\bwhat(?:'s| is) the date\b|\bwhat date is it\b",
    "weather": r"\bweather\b|\bforecast\b|\btemperature\b|\brain(?:ing|y)?\b|\bsnow(?:ing)?\b"
               r"|\bsunny\b|\bumbrella\b|\bwindy\b|\bdegrees\b|\bhumid(?:ity)?\b|\bstorms?\b"
               r"|\bfog(?:gy)?\b",
    "news": r"\bnews\b|\bheadlines?\b|\btop stor(?:y|ies)\b|\bcurrent events\b|\bpapers?\b",
    "related_topics": r"\brelated\b|\bsimilar\b|\btopics?\b|\b(?:linked|connected|associated)"
                      r" (?:to|with)\b",
    "map": r"\bwhere\b|\bmap\b|\blocated?\b|\bwhich room\b|\bhow do i get to\b",
    "music": r"\bsing\b|\bsongs?\b|\bmusic\b|\bdance\b|\btune\b|\blullaby\b"
             r"|\bplay (?!football|chess|cards|a game|with)",
    "photo": r"\bphoto(?:graph)?s?\b|\bpictures?\b|\bselfie\b|\bsnapshot\b|\bcamera\b|\bsnap\b"
             r"|\bpic\b|\bsay cheese\b",
    "information": r"^(?:who|what) (?:is|was|are|were)\b|^what's an?\b|\btell me about\b"
                   r"|\bexplain\b|\bdefine\b|\bfacts about\b|\bwho invented\b"
                   r"|^who (?:first )?(?:wrote|composed|painted|discovered|designed|founded)\b"
                   r"|^who (?:is|was) the (?:author|inventor|composer|painter) of\b",
}
_CUES = {label: re.compile(p) for label, p in CUES.items()}


@dataclass(frozen=True)
class Intent:
    """The route for one utterance: a label of :data:`LABELS`, how sure, and why."""

    label: str
    confidence: float
    cues: tuple[str, ...] = ()
    source: str = "model"  # or "mode" when an explicit mode decided


def load_utterances(path: str | Path, labels: tuple[str, ...] = LABELS
                    ) -> list[tuple[str, str]]:
    """``(label, utterance)`` pairs from a ``label<TAB>utterance`` file (``#`` comments)."""
    pairs = []
    for n, line in enumerate(read_text(path).splitlines(), 1):
        if not line.strip() or line.startswith("#"):
            continue
        label, sep, text = line.partition("\t")
        if not sep or label not in labels or not text.strip():
            raise DialogueError(f"{path}:{n}: expected '<label><TAB><utterance>' with a label "
                                f"in {', '.join(labels)}")
        pairs.append((label, text.strip()))
    return pairs


@cache
def _topics() -> frozenset[str]:
    return frozenset(KnowledgeBase.load().index)


@cache
def _song_names() -> frozenset[str]:
    return frozenset(normalise(c) for cues in shipped_songs().values() for c in cues)


def mask_entities(text: str) -> str:
    """Normalised ``text`` with songs, knowledge-base topics and places (after "in", "for",
    ...) replaced by the placeholder words ``zsong``, ``ztopic`` and ``zplace``."""
    words = normalise(text).split()
    out: list[str | None] = list(words)
    used = [False] * len(words)
    for i, j, phrase in ngrams(words, 4):
        if any(used[i:j]) or phrase in STOPWORDS or phrase in COMMON or phrase in TIME_WORDS:
            continue
        if phrase in _song_names():
            tag = "zsong"
        elif phrase.removeprefix("the ") in _topics():
            tag = "ztopic"
        elif i > 0 and words[i - 1] in PLACE_PREPOSITIONS and known_place(phrase):
            tag = "zplace"
        else:
            continue
        out[i:j] = [tag] + [None] * (j - i - 1)
        used[i:j] = [True] * (j - i)
    return " ".join(w for w in out if w)


def _features() -> object:
    # scikit-learn takes about a second to import: loaded with the first classifier, so
    # that the command line (which reads this module's constants) stays fast
    from sklearn.feature_extraction.text import TfidfVectorizer
    from sklearn.pipeline import make_pipeline, make_union
    from sklearn.preprocessing import FunctionTransformer

    def column(k: int) -> FunctionTransformer:
        return FunctionTransformer(lambda rows: [r[k] for r in rows])

    return make_union(
        make_pipeline(column(0), TfidfVectorizer(ngram_range=(1, 2), sublinear_tf=True)),
        make_pipeline(column(1), TfidfVectorizer(analyzer="char_wb", ngram_range=(2, 4),
                                                 sublinear_tf=True)))


def _rows(texts: list[str]) -> list[tuple[str, str]]:
    return [(mask_entities(t), normalise(t)) for t in texts]


class TextModel:
    """Logistic regression over the TF-IDF features of :func:`_features`, trained on
    ``(label, utterance)`` examples when made (well under a second)."""

    def __init__(self, examples: list[tuple[str, str]]) -> None:
        from sklearn.linear_model import LogisticRegression  # see _features
        from threadpoolctl import threadpool_limits

        labels, texts = zip(*examples, strict=True)
        self.features = _features()
        with threadpool_limits(limits=1):  # tiny problem: threads only add overhead
            x = self.features.fit_transform(_rows(list(texts)))  # type: ignore[attr-defined]
            model = LogisticRegression(C=10.0, max_iter=3000, class_weight="balanced")
            model.fit(x, labels)
        self.labels: tuple[str, ...] = tuple(model.classes_)
        self.coef = model.coef_.T.copy()
        self.intercept = model.intercept_.copy()

    def probabilities(self, text: str) -> np.ndarray:
        """The probability of each of :attr:`labels` for ``text``."""
        z = np.asarray(self.features.transform(_rows([text])) @ self.coef)[0] + self.intercept
        probs = np.exp(z - z.max())
        return probs / probs.sum()


class IntentClassifier:
    """TF-IDF + logistic regression over :data:`LABELS`, plus cue-word bonuses."""

    def __init__(self, examples: list[tuple[str, str]] | None = None,
                 cue_bonus: float = CUE_BONUS) -> None:
        self.model = TextModel(examples if examples is not None
                               else load_utterances(TRAIN_FILE))
        self.labels = self.model.labels
        self.cue_bonus = cue_bonus

    @classmethod
    @cache
    def default(cls) -> IntentClassifier:
        """The classifier trained on the shipped utterances (built once per process)."""
        return cls()

    def scores(self, text: str) -> tuple[dict[str, float], tuple[str, ...]]:
        """Normalised scores per label (model probability plus cue bonus) and the cues hit."""
        t = normalise(text)
        probs = self.model.probabilities(text)
        hits = tuple(label for label, cue in _CUES.items() if cue.search(t))
        raw = {label: float(p) + (self.cue_bonus if label in hits else 0.0)
               for label, p in zip(self.labels, probs, strict=True)}
        total = sum(raw.values())
        return {label: v / total for label, v in raw.items()}, hits

    def classify(self, text: str, mode: str | None = None) -> Intent:
        """The intent of ``text``; ``mode`` ("qa", "chitchat" or a category) overrides."""
        mode = mode or "auto"
        if mode not in MODES:
            raise DialogueError(f"unknown mode {mode!r}; choose from {', '.join(MODES)}")
        if mode not in ("auto", "qa"):
            return Intent(mode, 1.0, source="mode")
        scores, hits = self.scores(text)
        allowed = CATEGORIES if mode == "qa" else LABELS
        label = max(allowed, key=lambda k: scores[k])
        return Intent(label, scores[label], hits, "model" if mode == "auto" else "mode")


def evaluate_routing(classifier: IntentClassifier | None = None,
                     path: str | Path = HELDOUT_FILE) -> dict:
    """Accuracy of ``classifier`` on a labelled file, with per-label accuracy and the misses."""
    clf = classifier or IntentClassifier.default()
    pairs = load_utterances(path)
    misses, per_total, per_ok, times = [], Counter(), Counter(), []
    for label, text in pairs:
        t0 = time.perf_counter()
        got = clf.classify(text).label
        times.append((time.perf_counter() - t0) * 1000)
        per_total[label] += 1
        if got == label:
            per_ok[label] += 1
        else:
            misses.append({"text": text, "expected": label, "got": got})
    times.sort()
    return {"routing_accuracy": sum(per_ok.values()) / max(len(pairs), 1), "n": len(pairs),
            "per_label": {k: per_ok[k] / per_total[k] for k in LABELS if per_total[k]},
            "routing_ms_median": times[len(times) // 2] if times else 0.0,
            "misses": misses}
