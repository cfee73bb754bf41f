"""The QA bot: one entry point that sends a question to its category's answering function."""

from __future__ import annotations

import tempfile
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from core.config_files import read_yaml
from dialogue.qa import CATEGORIES
from dialogue.qa.base import Answer, DialogueError
from dialogue.qa.clock import Clock, answer_time, utc_now
from dialogue.qa.encyclopedia import Encyclopedia
from dialogue.qa.home_map import Household, answer_map
from dialogue.qa.knowledge import KnowledgeBase, answer_information, answer_related
from dialogue.qa.music import Songs, answer_music
from dialogue.qa.news import SAMPLE_FEED, answer_news
from dialogue.qa.photo import TakePhoto, answer_photo
from dialogue.qa.weather import ScenarioWeather, WeatherProvider, answer_weather

SAMPLE_WEATHER = Path(__file__).resolve().parents[1] / "data" / "weather_sample.yaml"


class QABot:
    """Answers questions of the eight categories from local providers only.

    Every provider is optional: a missing one gives a polite "I can't" answer.
    ``household`` feeds the map, ``take_photo`` saves a camera frame and returns its path,
    ``out_dir`` receives rendered maps (a temporary folder when not given), ``clock``
    returns the current aware datetime, ``home_city`` answers questions naming no city
    (default: the weather provider's home city) and ``songs`` are the songs the robot can
    sing and dance (default: the shipped routines); ``encyclopedia`` answers what the knowledge
    base does not hold ("shipped": WordNet where ``config/conversation.yaml`` says;
    None: the knowledge base alone).
    """

    def __init__(self, *, weather: WeatherProvider | None = None,
                 feed: str | Path | None = SAMPLE_FEED, knowledge: KnowledgeBase | None = None,
                 household: Household | None = None, out_dir: str | Path | None = None,
                 clock: Clock = utc_now, home_city: str | None = None,
                 take_photo: TakePhoto | None = None, songs: Songs | None = None,
                 encyclopedia: Encyclopedia | str | None = "shipped") -> None:
        self.weather = weather
        self.feed = feed
        self.knowledge = knowledge if knowledge is not None else KnowledgeBase.load()
        self.household = household
        self._out_dir = Path(out_dir) if out_dir else None
        self.clock = clock
        self.home_city = home_city or (weather.home_city if weather else None)
        self.take_photo = take_photo
        self.songs = songs
        self.encyclopedia = (Encyclopedia.shipped() if encyclopedia == "shipped"
                             else encyclopedia)

    @classmethod
    def offline(cls, **kwargs: Any) -> QABot:
        """A bot over the shipped sample data (weather block, news feed, knowledge base);
        keyword arguments replace any of them."""
        kwargs.setdefault("weather", load_weather())
        return cls(**kwargs)

    @property
    def out_dir(self) -> Path:
        """Where rendered maps go."""
        if self._out_dir is None:
            self._out_dir = Path(tempfile.mkdtemp(prefix="companion-dialogue-"))
        return self._out_dir

    def answer(self, category: str, text: str, *, last_topic: str | None = None,
               name: str | None = None) -> Answer:
        """Answer ``text`` as a question of ``category`` (one of :data:`CATEGORIES`)."""
        if category not in CATEGORIES:
            raise DialogueError(f"unknown QA category {category!r}; choose from "
                                f"{', '.join(CATEGORIES)}")
        if category == "time":
            return answer_time(text, self.clock, self.home_city)
        if category == "weather":
            return answer_weather(text, self.weather)
        if category == "news":
            return answer_news(text, self.feed)
        if category == "information":
            return answer_information(text, self.knowledge, last_topic, self.encyclopedia)
        if category == "related_topics":
            return answer_related(text, self.knowledge, last_topic)
        if category == "map":
            return answer_map(text, self.household, self.out_dir, self.knowledge)
        if category == "music":
            return answer_music(text, self.songs)
        return answer_photo(self.take_photo, name)


def load_weather(path: str | Path | Mapping[str, Any] = SAMPLE_WEATHER) -> ScenarioWeather:
    """A weather provider from a YAML/JSON file holding a weather block, or the block itself.

    A file may hold the block at its top level or under a ``weather`` key.
    """
    if isinstance(path, Mapping):
        return ScenarioWeather(path)
    data = read_yaml(path)
    return ScenarioWeather(data.get("weather", data), source=str(path))
