"""News category: headlines from a local RSS or Atom file, read with feedparser."""

from __future__ import annotations

import io
import re
from pathlib import Path

import feedparser

from core.files import read_bytes
from dialogue.qa.base import Answer, DialogueError
from dialogue.qa.text import content_words, normalise, word_set

SAMPLE_FEED = Path(__file__).resolve().parents[1] / "data" / "news_sample.xml"
NEWS_WORDS = word_set("""news headline headlines latest today today's happening world going
on new anything read top story stories recent current events any update updates paper
newspaper""")
MAX_HEADLINES = 3
CUES = word_set("""news headline headlines latest stories story paper papers happening happened
happen new events reported update updates""")
NOT_TOPICS = NEWS_WORDS | word_set("""good big important breaking local quick top week weekend
morning evening tonight yesterday lately day days this some people talking""")
ABOUT = re.compile(r"\b(?:about|on|regarding|concerning|in)\s+(.+)$")


def news_topic(text: str) -> list[str]:
    """The words naming what the news should be about, or none for the general headlines.
    Only the sentence that asks for news counts ("Look, I can still touch the sky! What's in
    the news today?" has no topic); there the topic follows ``about``/``on``/``in``
    ("any news about science", "what's new in the community") or stands right before a
    news word ("the latest sports news")."""
    clauses = [c for c in re.split(r"[.!?;]+", text) if c.strip()]
    asking = [c for c in clauses if CUES & set(normalise(c).split())] or clauses or [text]
    words = normalise(asking[-1]).split()
    cue = next((i for i, w in enumerate(words) if w in CUES), None)
    if cue is None:
        return [w for w in content_words(" ".join(words)) if w not in NOT_TOPICS]
    tail = ABOUT.search(" ".join(words[cue:]))
    after = [w for w in content_words(tail.group(1)) if w not in NOT_TOPICS] if tail else []
    if after:
        return after
    topical = set(content_words(" ".join(words))) - NOT_TOPICS
    return [w for i, w in enumerate(words[:-1]) if w in topical and words[i + 1] in CUES][-1:]


def _parse(data: bytes) -> feedparser.FeedParserDict:
    # as a stream: feedparser would take bytes that look like a path for a file to open
    return feedparser.parse(io.BytesIO(data))


def check_feed(path: str | Path) -> None:
    """Refuse a file that cannot be read (a :class:`~core.files.FileReadError`) or is not
    an RSS or Atom feed (a :class:`DialogueError`), naming it."""
    if not _parse(read_bytes(path)).version:
        raise DialogueError(f"{path}: not an RSS or Atom feed")


def read_feed(path: str | Path) -> tuple[list[dict[str, str]], str | None]:
    """The feed's entries (title, link, summary, category) and its link; empty when unreadable
    (the file is read again for every question, so a fetcher may refresh it meanwhile)."""
    try:
        data = read_bytes(path)
    except OSError:
        return [], None
    feed = _parse(data)
    entries = [{"title": e.get("title", "").strip(), "link": e.get("link", ""),
                "summary": e.get("summary", ""),
                "category": " ".join(t.get("term", "") for t in e.get("tags", []))}
               for e in feed.entries if e.get("title", "").strip()]
    return entries, feed.feed.get("link") or None


def _stem(word: str) -> str:
    return word[:-1] if word.endswith("s") and len(word) > 3 else word


def answer_news(text: str, feed_path: str | Path | None = SAMPLE_FEED) -> Answer:
    """Read the latest headlines, or those about the topic the question names."""
    entries, feed_link = read_feed(feed_path) if feed_path else ([], None)
    if not entries:
        return Answer("Sorry, I have no news to share right now.", found=False, topic="news")
    asked = news_topic(text)
    topic = [_stem(w) for w in asked]
    chosen = entries
    intro = "Here are the latest headlines"
    if topic:
        def matches(e: dict[str, str]) -> bool:
            words = {_stem(w) for w in content_words(" ".join(e.values()))}
            return any(t in words for t in topic)
        about = [e for e in entries if matches(e)]
        if about:
            chosen, intro = about, f"Here is the news about {' '.join(asked)}"
        else:
            intro = f"I found no news about {' '.join(asked)}; here are the latest headlines"
    titles = [e["title"].rstrip(".") for e in chosen[:MAX_HEADLINES]]
    return Answer(f"{intro}: " + "; ".join(titles) + ".",
                  tablet=chosen[0]["link"] or feed_link or str(feed_path),
                  topic=" ".join(topic) or "news")
