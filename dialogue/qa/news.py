"""News category: headlines from a local RSS or Atom file, read with feedparser."""

from __future__ import annotations

from pathlib import Path

import feedparser

from dialogue.qa.base import Answer
from dialogue.qa.text import content_words, word_set

SAMPLE_FEED = Path(__file__).resolve().parents[1] / "data" / "news_sample.xml"
NEWS_WORDS = word_set("""news headline headlines latest today today's happening world going
on new anything read top story stories recent current events any update updates paper
newspaper""")
MAX_HEADLINES = 3


def read_feed(path: str | Path) -> tuple[list[dict[str, str]], str | None]:
    """The feed's entries (title, link, summary, category) and its link; empty when unreadable."""
    try:
        data = Path(path).read_bytes()
    except OSError:
        return [], None
    feed = feedparser.parse(data)
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
    topic = [_stem(w) for w in content_words(text) if w not in NEWS_WORDS]
    chosen = entries
    intro = "Here are the latest headlines"
    if topic:
        def matches(e: dict[str, str]) -> bool:
            words = {_stem(w) for w in content_words(" ".join(e.values()))}
            return any(t in words for t in topic)
        about = [e for e in entries if matches(e)]
        if about:
            chosen, intro = about, f"Here is the news about {' '.join(topic)}"
        else:
            intro = f"I found no news about {' '.join(topic)}; here are the latest headlines"
    titles = [e["title"].rstrip(".") for e in chosen[:MAX_HEADLINES]]
    return Answer(f"{intro}: " + "; ".join(titles) + ".",
                  tablet=chosen[0]["link"] or feed_link or str(feed_path),
                  topic=" ".join(topic) or "news")
