"""Information retrieval and related topics from a local knowledge base (a JSON file), and
everyday knowledge from WordNet (:mod:`dialogue.qa.encyclopedia`) for what it does not hold.

The shipped base, ``dialogue/data/knowledge.json``, is written by the project: each entry
has a ``title``, ``aliases``, a short ``summary``, the ``url`` the tablet shows, a list of
``related`` topics and, for landmarks, ``lat``/``lon`` (used by the map category).
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass
from pathlib import Path
from urllib.parse import quote

from dialogue.qa.base import Answer, DialogueError
from dialogue.qa.encyclopedia import Encyclopedia, Fact
from dialogue.qa.text import (
    AGENT_OF,
    STOPWORDS,
    WHO_MADE,
    best_match,
    ngrams,
    normalise,
    original_words,
    strip_frame,
    topic_phrase,
)

KNOWLEDGE = Path(__file__).resolve().parents[1] / "data" / "knowledge.json"
RELATED_FRAMES = [r"(?:topics|things|subjects)? ?(?:are |is )?(?:related|linked|connected|similar)"
                  r" (?:to|with)", r"(?:topics|things|subjects) like", r"similar to",
                  r"related topics(?: for| of| about)?", r"goes with", r"besides", r"after"]
MAX_RELATED = 5
WIKI = "https://en.wikipedia.org/wiki/"
WHO = re.compile(r"\bwho(?:'s| is| was| are| were)?\b")


@dataclass(frozen=True)
class Entry:
    """One topic of the knowledge base."""

    title: str
    summary: str
    url: str
    related: tuple[str, ...]
    aliases: tuple[str, ...] = ()
    lat: float | None = None
    lon: float | None = None


class KnowledgeBase:
    """Entries by normalised title and alias, with fuzzy lookup."""

    def __init__(self, entries: list[Entry]) -> None:
        self.entries = entries
        self.index: dict[str, Entry] = {}
        for e in entries:
            for name in (e.title, *e.aliases):
                key = normalise(name)
                self.index.setdefault(key.removeprefix("the "), e)

    @classmethod
    def load(cls, path: str | Path = KNOWLEDGE) -> KnowledgeBase:
        """Read a knowledge base file; a missing or malformed file is a :class:`DialogueError`."""
        try:
            data = json.loads(Path(path).read_text(encoding="utf-8"))
            entries = [Entry(title=d["title"], summary=d["summary"], url=d["url"],
                             related=tuple(d.get("related", ())),
                             aliases=tuple(d.get("aliases", ())),
                             lat=d.get("lat"), lon=d.get("lon")) for d in data["entries"]]
        except (OSError, ValueError, KeyError, TypeError) as exc:
            raise DialogueError(f"{path}: cannot read the knowledge base ({exc})") from None
        return cls(entries)

    def get(self, phrase: str) -> Entry | None:
        """The entry called exactly ``phrase`` (ignoring case, articles, a plural s)."""
        key = normalise(phrase).removeprefix("the ")
        return self.index.get(key) or (self.index.get(key[:-1]) if key.endswith("s") else None)

    def find(self, text: str) -> Entry | None:
        """The entry a sentence is about: the longest phrase that names one, else a near match."""
        words = normalise(text).split()
        for _, _, phrase in ngrams(words, 5):
            if phrase in STOPWORDS:
                continue
            entry = self.get(phrase)
            if entry:
                return entry
        phrase = strip_frame(text)
        close = best_match(phrase, self.index) if phrase else None
        return self.index[close] if close else None

    def related(self, entry: Entry) -> list[str]:
        """Topics related to ``entry``: its own list, then entries that list it."""
        out = [(self.get(r) or r) for r in entry.related]
        out = [r.title if isinstance(r, Entry) else r for r in out]
        for other in self.entries:
            if other is not entry and any(self.get(r) is entry for r in other.related):
                out.append(other.title)
        seen: set[str] = set()
        return [t for t in out if not (normalise(t) in seen or seen.add(normalise(t)))]


def _topic(text: str, last_topic: str | None, frames: list[str] = ()) -> str:
    phrase = strip_frame(text, frames)
    if phrase in {"", "it", "that", "them", "this", "more", "him", "her"} and last_topic:
        return last_topic
    return phrase


def answer_information(text: str, kb: KnowledgeBase, last_topic: str | None = None,
                       encyclopedia: Encyclopedia | None = None) -> Answer:
    """Describe what the question asks about, or say clearly that the robot does not know.
    The household's own knowledge base wins; then WordNet (``encyclopedia``): who made a
    thing, or what (who) a thing (person) is."""
    entry = kb.find(text)
    topic = _topic(text, last_topic)
    if entry is None and topic == last_topic and last_topic:
        entry = kb.find(last_topic)
    if entry is not None:
        return Answer(entry.summary, tablet=entry.url, topic=entry.title)
    more = topic == last_topic and "more" in normalise(text).split()  # "tell me more"
    fact = _look_up(text, topic, encyclopedia, more) if encyclopedia and topic else None
    if fact is not None:
        return Answer(fact.text, tablet=f"{WIKI}{quote(fact.topic.replace(' ', '_'))}",
                      topic=fact.topic)
    named = topic_phrase(text) if topic != last_topic else topic
    about = f" about {named}" if named else " about that"
    return Answer(f"I'm sorry, I don't know anything{about} yet.", found=False,
                  topic=named or None)


def _look_up(text: str, topic: str, encyclopedia: Encyclopedia, more: bool) -> Fact | None:
    t = normalise(text)
    made = WHO_MADE.search(t) or AGENT_OF.search(t)
    if made:
        return encyclopedia.who_made(made.group(1), made.group(2))
    who = WHO.search(t) is not None
    asked = original_words(text, topic)
    words = topic.split()
    for n in range(len(words), 0, -1):  # the whole phrase, then its head ("the Nile river")
        phrase = " ".join(words[len(words) - n:])
        fact = encyclopedia.describe(phrase, who, asked if n == len(words) else phrase, more)
        if fact is not None:
            return fact
    return None


def answer_related(text: str, kb: KnowledgeBase, last_topic: str | None = None) -> Answer:
    """List topics related to the one named (or to the last topic of the conversation)."""
    topic = _topic(text, last_topic, RELATED_FRAMES)
    entry = kb.find(topic) if topic else None
    if entry is None and last_topic and not topic:
        entry = kb.find(last_topic)
    if entry is None:
        about = topic or "that"
        return Answer(f"I'm sorry, I don't know which topics are related to {about}.",
                      found=False, topic=topic or None)
    related = kb.related(entry)[:MAX_RELATED]
    listed = ", ".join(related[:-1]) + f" and {related[-1]}" if len(related) > 1 else related[0]
    return Answer(f"Topics related to {entry.title}: {listed}.", tablet=entry.url,
                  topic=entry.title)
