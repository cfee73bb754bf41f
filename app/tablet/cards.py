"""What the tablet shows for a reply, drawn by the project itself from local data only.

A reply's ``tablet`` target is often an external address (time.is, a weather site, a news
link, an encyclopaedia, a map service). The tablet never loads one: it shows a card built
from the same local data the QA bot answered from (the bot's clock, the scenario's weather
block, the news feed, the knowledge base, the household map and photos), and the original
address as plain text. Files (maps, photos) are handed out by id (:class:`FileRegistry`).
"""

from __future__ import annotations

import re
import threading
from collections import OrderedDict
from pathlib import Path
from typing import Any
from urllib.parse import parse_qs, urlsplit
from zoneinfo import ZoneInfo, ZoneInfoNotFoundError

from dialogue.qa.bot import QABot
from dialogue.qa.news import read_feed
from dialogue.qa.places import lookup

IMAGE_TYPES = {".png": "image/png", ".jpg": "image/jpeg", ".jpeg": "image/jpeg"}
WEATHER_DAY = re.compile(r"^The weather in .+? (?P<day>[\w ]+?): ")
MAX_NEWS = 8
MAX_RELATED = 5


class FileRegistry:
    """Image files the tablet may show, each under an opaque id: only regular image files
    inside ``root`` are accepted, and the client only ever names an id, never a path. The
    ``limit`` most recent files are kept."""

    def __init__(self, root: Path, limit: int = 500) -> None:
        self.root = root.resolve()
        self.limit = limit
        self._by_id: OrderedDict[str, Path] = OrderedDict()
        self._lock = threading.Lock()
        self._count = 0

    def add(self, path: str | Path) -> str | None:
        """Register ``path``; its id, or None when it is not an image inside the root."""
        resolved = Path(path).resolve()
        if (resolved.suffix.lower() not in IMAGE_TYPES or not resolved.is_file()
                or not resolved.is_relative_to(self.root)):
            return None
        with self._lock:
            self._count += 1
            file_id = f"f{self._count}"
            self._by_id[file_id] = resolved
            while len(self._by_id) > self.limit:
                self._by_id.popitem(last=False)
        return file_id

    def get(self, file_id: str) -> tuple[Path, str] | None:
        """The file registered as ``file_id`` and its media type, or None."""
        with self._lock:
            path = self._by_id.get(file_id)
        return (path, IMAGE_TYPES[path.suffix.lower()]) if path is not None else None


def _is_url(target: str | None) -> bool:
    return bool(target) and urlsplit(target).scheme in ("http", "https")


def card_for(record: dict[str, Any], qa: QABot, topic: str | None,
             files: FileRegistry) -> dict[str, Any] | None:
    """The card for a reply ``record`` (the manager's plain data), or None when the reply
    points at nothing (chit-chat, "I don't know"). ``topic`` is the conversation's topic
    after the reply (the city, entry, song ...)."""
    target = record.get("tablet")
    if not record.get("found", True) or not target:
        return None
    route = record["route"]
    card: dict[str, Any] = {"kind": route, "link": target if _is_url(target) else None}
    build = _BUILDERS.get(route)
    extra = build(record, qa, topic, files) if build is not None else None
    return {**card, **extra} if extra is not None else card


def _clock(record: dict[str, Any], qa: QABot, topic: str | None, files: FileRegistry
           ) -> dict[str, Any]:
    now = qa.clock()
    place = lookup(topic) if topic and topic != "time" else None
    try:
        local = now.astimezone(ZoneInfo(place.timezone)) if place else now.astimezone()
    except ZoneInfoNotFoundError:
        local = now
    return {"kind": "clock", "city": place.name if place else "here",
            "hour": local.hour, "minute": local.minute, "second": local.second,
            "time": f"{local:%H:%M}", "date": f"{local:%A} {local.day} {local:%B}",
            "zone": str(local.tzinfo)}


def _weather(record: dict[str, Any], qa: QABot, topic: str | None, files: FileRegistry
             ) -> dict[str, Any] | None:
    if qa.weather is None or not topic:
        return None
    asked = WEATHER_DAY.match(record["text"])
    days = []
    for day in qa.weather.days(topic):
        report = qa.weather.report(topic, day)
        if report is not None:
            days.append({"day": day, "current": bool(asked and asked["day"] == day),
                         **report.day_data.model_dump(exclude_none=True)})
    return {"kind": "weather", "city": topic, "days": days}


def _news(record: dict[str, Any], qa: QABot, topic: str | None, files: FileRegistry
          ) -> dict[str, Any]:
    entries, _ = read_feed(qa.feed) if qa.feed else ([], None)
    said = record["text"]
    items = [{"title": e["title"], "summary": re.sub(r"<[^>]+>", "", e["summary"])[:300],
              "category": e["category"], "link": e["link"],
              "current": e["title"].rstrip(".") in said} for e in entries]
    items.sort(key=lambda e: not e["current"])   # the headlines the robot read come first
    return {"kind": "news", "items": items[:MAX_NEWS]}


def _knowledge(record: dict[str, Any], qa: QABot, topic: str | None, files: FileRegistry
               ) -> dict[str, Any] | None:
    entry = (qa.knowledge.get(topic) or qa.knowledge.find(topic)) if topic else None
    if entry is None:
        return None
    return {"kind": "knowledge", "title": entry.title, "summary": entry.summary,
            "related": qa.knowledge.related(entry)[:MAX_RELATED]}


def _image(record: dict[str, Any], qa: QABot, topic: str | None, files: FileRegistry
           ) -> dict[str, Any] | None:
    target = record["tablet"]
    if _is_url(target):   # a city or landmark on the world map: its coordinates
        query = parse_qs(urlsplit(target).query)
        try:
            lat, lon = float(query["mlat"][0]), float(query["mlon"][0])
        except (KeyError, ValueError):
            return None
        return {"kind": "place", "title": topic, "lat": lat, "lon": lon}
    file_id = files.add(target)
    if file_id is None:
        return None
    return {"kind": "image", "title": topic, "src": f"/api/file/{file_id}"}


def _song(record: dict[str, Any], qa: QABot, topic: str | None, files: FileRegistry
          ) -> dict[str, Any]:
    return {"kind": "song", "title": topic}


_BUILDERS = {"time": _clock, "weather": _weather, "news": _news, "information": _knowledge,
             "related_topics": _knowledge, "map": _image, "photo": _image, "music": _song}
