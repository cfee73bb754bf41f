"""Everyday things and famous people for the household language model: the robot's own
lines name only the few topics their writers thought of ("what is a penguin"), so spoken
questions about anything else ("what is a volcano") could not be recognised.

The topics come from WordNet (read in place, as the knowledge answers read it): its
single-word nouns and its named people, ranked by how common their words are in general
English, as the unigram probabilities of the general en-US language model inside the
pocketsphinx wheel measure it; the ``nouns`` and ``people`` most common are kept. Each is
said once in a question frame drawn from ``noun_frames`` or ``people_frames``
(``topics`` in ``config/speech.yaml``). WordNet is the folder the knowledge answers
read (``knowledge.wordnet_dir`` in ``config/conversation.yaml``).
"""

from __future__ import annotations

import random
from collections.abc import Callable
from pathlib import Path

from dialogue.qa.wordnet import WordNet
from dialogue.speech.config import TopicsConfig
from dialogue.speech.engines import wheel_model_dir
from dialogue.speech.words import spoken_words

UNKNOWN = -(2 ** 29)   # pocketsphinx's log probability of a word its model lacks


def general_english() -> Callable[[str], int]:
    """The log unigram probability of a word in the wheel's general en-US model."""
    from pocketsphinx import Config, LogMath, NGramModel

    model = NGramModel(Config(loglevel="FATAL"), LogMath(),
                       str(wheel_model_dir() / "en-us.lm.bin"))
    return lambda word: model.prob([word])


def wordnet_nouns(folder: Path) -> list[str]:
    """WordNet's single-word nouns (letters only)."""
    with (folder / "index.noun").open(encoding="utf-8") as fh:
        lemmas = (line.split(" ", 1)[0] for line in fh if not line.startswith(" "))
        return [w for w in lemmas if w.isalpha()]


def topic_lines(cfg: TopicsConfig, wordnet_dir: Path, known: set[str]) -> list[list[str]]:
    """One question (as spoken words) for each of the most common nouns and people whose
    words are all in ``known``; nothing when WordNet is missing."""
    wordnet = WordNet.load(wordnet_dir)
    if wordnet is None:
        return []
    logp = general_english()

    def score(words: list[str]) -> float:
        probs = [logp(w) for w in words]
        return sum(probs) if all(p > UNKNOWN for p in probs) else float("-inf")

    nouns = {w for w in wordnet_nouns(wordnet_dir) if w in known}
    people = {tuple(words) for s in wordnet.people()
              if (words := spoken_words(s.lemmas[0])) and all(w in known for w in words)}
    ranked_nouns = sorted(nouns, key=lambda w: (-score([w]), w))[:cfg.nouns]
    ranked_people = sorted(people, key=lambda p: (-score(list(p)), p))[:cfg.people]
    rng = random.Random(cfg.seed)
    lines = [rng.choice(cfg.noun_frames).format(w) for w in ranked_nouns]
    lines += [rng.choice(cfg.people_frames).format(" ".join(p)) for p in ranked_people]
    return [spoken_words(line) for line in lines]
