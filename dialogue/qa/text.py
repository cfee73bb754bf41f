"""Light text helpers: normalising, fuzzy lookup, and pulling a keyword out of a question.

This replaces the thesis's NLTK tagger with a documented lightweight alternative: strip the
question frame ("what is", "tell me about", ...) and function words, keep what remains.
"""

from __future__ import annotations

import difflib
import re
import unicodedata
from collections.abc import Iterable


def word_set(words: str) -> frozenset[str]:
    """The whitespace-separated words of ``words`` as a set."""
    return frozenset(words.split())


WORD = re.compile(r"[a-z0-9]+(?:['\u2019][a-z]+)?")

STOPWORDS = word_set("""
a an the of in on at to for from with by about into over under near and or but is are was
were be been being am do does did can could would will shall should may might must please
me my mine you your yours we our us i it its it's this that these those there here what
what's whats who who's whos whom which when where where's how how's why tell show give
some any robot hey hi hello ok okay so just really very like again now right know let let's
""")

ARTICLES = frozenset({"a", "an", "the"})
# words after the topic that belong to the question: "what is the moon made of", "... today"
TRAILING = word_set("today now tonight then made used called known famous good")

MADE = r"invented|discovered|wrote|composed|painted|created|designed|founded|built|developed"
AGENTS = (r"author|writer|inventor|composer|painter|creator|designer|founder|discoverer"
          r"|architect|sculptor")
WHO_MADE = re.compile(rf"\bwho (?:first |originally |really )?({MADE})\s+(?:the )?(.+)$")
AGENT_OF = re.compile(rf"\bwho (?:is|was) the ({AGENTS}) of\s+(?:the )?(.+)$")
FRAMES = [  # question frames removed before a topic is looked up; longest first
    rf"who (?:is|was) the (?:{AGENTS}) of", rf"who (?:first |originally |really )?(?:{MADE})",
    r"can you tell me (?:something |a bit |more )?about",
    r"tell me (?:something |a bit |more )?about", r"what do you know about",
    r"do you know (?:anything )?about", r"i(?:'d| would) like to know about",
    r"what (?:is|are|was|were)(?: an?| the)?", r"who (?:is|are|was|were)(?: the)?",
    r"what's(?: an?| the)?", r"who's", r"explain", r"define", r"describe",
    r"what does .* mean", r"information (?:on|about)", r"facts about", r"look up", r"search for",
]


def normalise(text: str) -> str:
    """Lower case, accents folded, punctuation turned into spaces, spaces collapsed."""
    folded = unicodedata.normalize("NFKD", text).encode("ascii", "ignore").decode()
    return " ".join(WORD.findall(folded.lower().replace("\u2019", "'")))


def original_words(text: str, phrase: str) -> str:
    """``phrase`` (normalised, as :func:`strip_frame` returns it) as ``text`` wrote it, with
    the article in front of it if any ("tell me about the Eiffel Tower" -> "the Eiffel Tower");
    ``phrase`` itself when it is not in ``text`` word for word."""
    folded = unicodedata.normalize("NFKD", text).encode("ascii", "ignore").decode()
    raw = re.findall(r"[A-Za-z0-9]+(?:['\u2019][A-Za-z]+)?", folded.replace("\u2019", "'"))
    low = [w.lower() for w in raw]
    want = phrase.split()
    for i in range(len(low) - len(want), -1, -1):
        if want and low[i:i + len(want)] == want:
            start = i - 1 if i and low[i - 1] in ARTICLES else i
            return " ".join(raw[start:i + len(want)])
    return phrase


def topic_phrase(text: str, extra: Iterable[str] = ()) -> str:
    """What a question is about, as the person wrote it, without the frame or an article:
    "tell me about the Eiffel Tower" -> "Eiffel Tower"; "" when it names nothing."""
    words = original_words(text, strip_frame(text, extra)).split()
    return " ".join(words[1:] if words and words[0].lower() in ARTICLES else words)


def content_words(text: str) -> list[str]:
    """The words of ``text`` that are not function words."""
    return [w for w in normalise(text).split() if w not in STOPWORDS]


def ngrams(words: list[str], longest: int = 4) -> Iterable[tuple[int, int, str]]:
    """``(start, end, phrase)`` for every n-gram up to ``longest`` words, longest first."""
    for n in range(min(longest, len(words)), 0, -1):
        for i in range(len(words) - n + 1):
            yield i, i + n, " ".join(words[i:i + n])


def best_match(phrase: str, choices: Iterable[str], cutoff: float = 0.85) -> str | None:
    """The choice closest to ``phrase`` (difflib ratio at least ``cutoff``), or None."""
    found = difflib.get_close_matches(phrase, list(choices), n=1, cutoff=cutoff)
    return found[0] if found else None


def strip_frame(text: str, extra: Iterable[str] = ()) -> str:
    """``text`` without its question frame, trailing politeness and edge function words."""
    t = normalise(text)
    for frame in [*extra, *FRAMES]:
        stripped = re.sub(rf"^(?:.*?\b)?{frame}\b", "", t, count=1).strip()
        if stripped != t:
            t = stripped
            break
    words = t.split()
    while words and words[0] in STOPWORDS:
        words.pop(0)
    while words and words[-1] in STOPWORDS | TRAILING:
        words.pop()
    return " ".join(words)
