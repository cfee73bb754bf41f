"""The QA bot's eight categories answer seeded questions offline; bad input gets a polite no."""

from datetime import UTC, datetime
from pathlib import Path

import cv2
import pytest

from dialogue.qa.base import DialogueError
from dialogue.qa.bot import QABot, load_weather
from dialogue.qa.clock import answer_time, scenario_clock
from dialogue.qa.home_map import Household, answer_map, plan_from_scenario, render_plan
from dialogue.qa.knowledge import KnowledgeBase, answer_information, answer_related
from dialogue.qa.music import answer_music, shipped_songs
from dialogue.qa.news import answer_news, news_topic
from dialogue.qa.photo import answer_photo
from dialogue.qa.weather import ScenarioWeather, WeatherProvider, answer_weather
from sim.scenario import load_scenario

NOON_UTC = datetime(2025, 6, 1, 12, 0, tzinfo=UTC)
WORLDS = Path(__file__).resolve().parents[1] / "worlds"
BLOCK = {"home": "Taipei",
         "cities": {"Taipei": {"today": {"condition": "sunny", "temp_c": 30}},
                    "Lisbon": {"today": {"condition": "clear", "temp_c": 24},
                               "next_week": {"condition": "showers", "temp_c": 19,
                                             "rain_chance": 40}}}}
ROOMS = [{"name": "living_room", "x": [0, 6], "y": [0, 5]},
         {"name": "kitchen", "x": [6, 9], "y": [0, 5]}]
ITEMS = [{"name": "sofa", "x": 3.0, "y": 4.4, "kind": "furniture", "type": "sofa"},
         {"name": "mug_0", "x": 8.5, "y": 4.5, "kind": "object", "type": "mug"},
         {"name": "Grace", "x": 1.0, "y": 3.0, "kind": "person"}]


@pytest.fixture(scope="module")
def kb() -> KnowledgeBase:
    return KnowledgeBase.load()


# -- time -------------------------------------------------------------------------------
def test_time_in_a_city_and_a_country() -> None:
    a = answer_time("What time is it in Tokyo right now?", lambda: NOON_UTC)
    assert "21:00" in a.text and "Tokyo" in a.text and a.tablet.endswith("/Tokyo")
    a = answer_time("what time is it in new york", lambda: NOON_UTC)
    assert "08:00" in a.text and "New York City" in a.text
    assert "Japan (Tokyo)" in answer_time("and in Japan?", lambda: NOON_UTC).text


def test_scenario_clock() -> None:
    clock = scenario_clock("23:40", "Asia/Taipei", lambda: 600.0)
    assert "23:50" in answer_time("what time is it?", clock, "Taipei").text
    assert "17:50" in answer_time("what time is it in Berlin?", clock).text


def test_time_at_home_and_unknown_city() -> None:
    assert "20:00" in answer_time("what time is it?", lambda: NOON_UTC, "Taipei").text
    a = answer_time("What time is it in Narnia?", lambda: NOON_UTC)
    assert not a.found and "Narnia" in a.text and "don't know" in a.text


# -- weather ----------------------------------------------------------------------------
def test_weather_from_a_block() -> None:
    provider = ScenarioWeather(BLOCK)
    assert isinstance(provider, WeatherProvider)
    a = answer_weather("What's the weather going to be like in Lisbon next week?", provider)
    assert "Lisbon next week: showers, 19 degrees" in a.text and "40 percent" in a.text
    assert "weather-forecast.com" in a.tablet
    assert "Taipei today: sunny" in answer_weather("Is it sunny today?", provider).text
    tomorrow = answer_weather("weather in Lisbon tomorrow", provider)
    assert "only for today, next week" in tomorrow.text
    # no city named ("to rain", "in the garden" are not places): the home city's weather
    garden = answer_weather("Is it going to rain tomorrow? I'd like to sit in the garden.",
                            provider)
    assert garden.found and "Taipei" in garden.text
    # an everyday word before a preposition is not a town ("in time for": not Time, Norway)
    picnic = answer_weather("will it be sunny in time for the picnic", provider)
    assert picnic.found and "Taipei" in picnic.text
    assert "Nice" in answer_weather("What's the weather in Nice for the weekend?",
                                    provider).text


def test_weather_missing_city_and_bad_block() -> None:
    provider = ScenarioWeather(BLOCK)
    assert "no weather report for Paris" in answer_weather("Is it raining in Paris?",
                                                           provider).text
    assert "Narnia" in answer_weather("weather in Narnia", provider).text
    assert not answer_weather("weather?", None).found
    with pytest.raises(DialogueError, match="temp_c"):
        ScenarioWeather({"cities": {"Rome": {"today": {"condition": "hot"}}}})
    assert load_weather().home_city == "Taipei"


# -- news -------------------------------------------------------------------------------
def test_news_headlines_and_topic() -> None:
    a = answer_news("What's in the news today?")
    assert a.text.startswith("Here are the latest headlines") and a.text.count(";") == 2
    assert a.tablet.startswith("https://")
    assert "football" in answer_news("any sports news?").text


@pytest.mark.parametrize(("text", "topic"), [
    ("Look, I can still touch the sky! What's in the news today?", []),
    ("Any good news today?", []),
    ("Is there any news about science?", ["science"]),
    ("Tell me the latest sports news.", ["sports"]),
    ("What's new in the community?", ["community"]),
])
def test_news_topic_comes_from_the_request_only(text: str, topic: list[str]) -> None:
    assert news_topic(text) == topic


def test_news_empty_and_missing_feed(tmp_path: Path) -> None:
    empty = tmp_path / "empty.xml"
    empty.write_text("<rss version='2.0'><channel><title>x</title></channel></rss>")
    for feed in (empty, tmp_path / "missing.xml", None):
        a = answer_news("what's the news?", feed)
        assert not a.found and "no news" in a.text
    atom = tmp_path / "atom.xml"
    atom.write_text("<feed xmlns='http://www.w3.org/2005/Atom'><title>t</title><entry>"
                    "<title>Robots learn to knit</title><link href='https://e.org/k'/>"
                    "</entry></feed>")
    a = answer_news("news please", atom)
    assert "Robots learn to knit" in a.text and a.tablet == "https://e.org/k"


# -- information and related topics -----------------------------------------------------
def test_information(kb: KnowledgeBase) -> None:
    a = answer_information("Who was Mozart?", kb)
    assert "1756" in a.text and a.tablet.endswith("Wolfgang_Amadeus_Mozart")
    assert "8,849" in answer_information("How tall is Mount Everest?", kb).text
    follow = answer_information("tell me more about it", kb, last_topic="Mars")
    assert "fourth planet" in follow.text


def test_information_unknown(kb: KnowledgeBase) -> None:
    a = answer_information("What is quantum chromodynamics?", kb)
    assert not a.found and "don't know anything about quantum chromodynamics" in a.text


def test_related_topics(kb: KnowledgeBase) -> None:
    a = answer_related("What topics are related to jazz?", kb)
    assert a.text.startswith("Topics related to jazz:") and "classical music" in a.text
    assert "Beethoven" in answer_related("related topics please", kb, "Mozart").text
    assert not answer_related("what is related to zorbing?", kb).found


# -- map --------------------------------------------------------------------------------
def test_map_marks_a_room_or_object(tmp_path: Path) -> None:
    house = Household(ROOMS, ITEMS)
    a = answer_map("Where did I leave my mug?", house, tmp_path)
    assert "north-east of the kitchen" in a.text
    img = cv2.imread(a.tablet)
    assert img is not None and img.shape[0] > 100
    assert "living room" in answer_map("where is the couch", house, tmp_path).text
    assert answer_map("Where's Grace?", house, tmp_path).text.startswith("Grace is")
    assert Path(answer_map("show me the kitchen", house, tmp_path).tablet).is_file()
    whole = answer_map("Show me the map of the house.", house, tmp_path)
    assert whole.text == "Here is the map of the house: living room, kitchen."


def test_map_cities_landmarks_and_unknown(tmp_path: Path, kb: KnowledgeBase) -> None:
    a = answer_map("Where is Nairobi?", None, tmp_path, kb)
    assert "1.28 degrees south" in a.text and "openstreetmap" in a.tablet
    assert "27.99 degrees north" in answer_map("where is mount everest", None, tmp_path,
                                               kb).text
    a = answer_map("Where are my glasses?", Household(ROOMS, ITEMS), tmp_path, kb)
    assert not a.found and "glasses" in a.text


def test_render_plan_and_scenario_plan(tmp_path: Path) -> None:
    out = render_plan(ROOMS, ITEMS, tmp_path / "plan.png", mark="kitchen")
    assert cv2.imread(str(out)).shape[2] == 3
    house = plan_from_scenario(load_scenario(WORLDS / "living_room.yaml"))
    a = answer_map("where is the teddy bear?", house, tmp_path)
    assert "on the bookshelf" in a.text and "living room" in a.text


# -- music and photo --------------------------------------------------------------------
def test_music_songs_are_the_dance_routines() -> None:
    assert list(shipped_songs()) == ["Tea Time Waltz", "Good Morning Sunshine", "Gears and Grooves",
                           "Happy Birthday", "Twinkle, Twinkle, Little Star"]
    for question, song in [("Robot, can you play 'Happy Birthday' for Mia?", "Happy Birthday"),
                           ("sing twinkle twinkle for the kids", "Twinkle, Twinkle, Little Star"),
                           ("Would you sing the birthday song?", "Happy Birthday"),
                           ("Dance with me, robot!", "Tea Time Waltz")]:
        a = answer_music(question)
        assert a.action.name == "sing_dance" and a.action.params["song"] == song
    for unknown in ("Could you play 'Moon River' for me?",
                    "Can you sing 'You Are My Sunshine' for us?"):
        a = answer_music(unknown)
        assert a.action is None and not a.found and "Happy Birthday" in a.text
    assert "don't know Yesterday yet" in answer_music("play a song called Yesterday").text
    # a misheard request is not echoed as a title: "music" names no song, so a known one
    misheard = answer_music("could you play music what is was lighthouse my favorite drink")
    assert misheard.action.name == "sing_dance" and "Lighthouse" not in misheard.text
    own = {"Lullaby": ("lullaby", "sleep song")}
    assert answer_music("sing me the sleep song", own).action.params["song"] == "Lullaby"


def test_photo(tmp_path: Path) -> None:
    a = answer_photo()
    assert a.action.name == "take_photo" and a.tablet is None
    shot = tmp_path / "frame.png"
    a = answer_photo(lambda: shot, name="Mia")
    assert a.tablet == str(shot) and a.action.params["path"] == str(shot) and "Mia" in a.text

    def broken() -> str:
        raise RuntimeError("no camera")

    a = answer_photo(broken)
    assert a.action is None and not a.found


def test_bot_dispatches_every_category(tmp_path: Path) -> None:
    bot = QABot.offline(out_dir=tmp_path, clock=lambda: NOON_UTC)
    assert "20:00" in bot.answer("time", "what time is it").text  # home city Taipei
    with pytest.raises(DialogueError):
        bot.answer("horoscope", "what's my horoscope?")
