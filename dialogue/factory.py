"""Where the robot's dialogue is put together: the manager of a household run, the manager of
an interactive ``companion chat`` session, the shipped chit-chat and mood style-transfer
models, the reply log and the robot's mood for a chat session.

In a household run the QA bot knows the scenario's household map and weather, tells the
scenario's time (its ``time_of_day`` in the home city's time zone, moved on by the simulated
seconds) and takes photos with the robot's camera; chit-chat replies come from the shipped
seq2seq model, restyled by the shipped mood style-transfer model behind its gate.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from dialogue.acts.config import load_acts_config
from dialogue.acts.model import HEADS_FILE
from dialogue.acts.replies import CompanionTalk
from dialogue.chat.config import DEFAULT_CHAT_MODEL
from dialogue.chat.model import ChitChatModel
from dialogue.manager import DialogueManager
from dialogue.qa.bot import QABot, load_weather
from dialogue.qa.clock import scenario_clock
from dialogue.qa.home_map import plan_from_scenario
from dialogue.qa.music import Songs
from dialogue.qa.news import SAMPLE_FEED, check_feed
from dialogue.qa.places import lookup
from dialogue.speech.config import load_speech_config
from dialogue.style.mood import MoodStyler
from dialogue.style.transfer import DEFAULT_STYLE_MODEL
from mind.homeostasis import Homeostasis
from mind.personality import DRIVES, load_personality
from sim.camera import scenario_camera
from sim.scenario import Scenario, load_scenario


def reply_logger(path: Path) -> Callable[[dict[str, Any]], None]:
    """Append each reply (with its route, action and tablet) to a JSON-lines file, flushed."""
    path.parent.mkdir(parents=True, exist_ok=True)

    def log(record: dict[str, Any]) -> None:
        with path.open("a", encoding="utf-8") as fh:
            fh.write(json.dumps(record, default=str) + "\n")

    return log


def shipped_chitchat() -> ChitChatModel | None:
    """The shipped chit-chat model, or None while none has been trained."""
    return ChitChatModel.load(DEFAULT_CHAT_MODEL) if DEFAULT_CHAT_MODEL.is_file() else None


def shipped_style() -> MoodStyler | None:
    """The shipped mood style-transfer model behind its gate (``config/mood_style.yaml``:
    the styled reply only when it keeps meaning and grammar, else the reply with a mood
    opening), or None while no model has been trained."""
    return MoodStyler.load() if DEFAULT_STYLE_MODEL.is_file() else None


def shipped_talk(staff: bool = False) -> CompanionTalk | None:
    """The robot's replies to what people share (``config/acts.yaml``) with the shipped act
    model, or None while none has been trained; ``staff``: care staff are there to call."""
    folder = load_acts_config().resolved_model_dir()
    return CompanionTalk.load(staff) if (folder / HEADS_FILE).is_file() else None


def household_dialogue(scenario: Scenario, elapsed: Callable[[], float], out_dir: Path,
                       take_photo: Callable[[], str | Path] | None = None,
                       style: Any = "shipped", songs: Songs | None = None) -> DialogueManager:
    """A manager for a run of ``scenario``; replies are appended to ``out_dir/dialogue.jsonl``.
    ``style``: a style-transfer model, None for none, or "shipped" for the shipped one;
    ``songs``: what the robot can sing (the run's dance routines; default the shipped ones)."""
    weather = (load_weather(scenario.weather.model_dump(exclude_none=True))
               if scenario.weather is not None else load_weather())
    home = lookup(weather.home_city) if weather.home_city else None
    clock = scenario_clock(scenario.time_of_day, home.timezone if home else "UTC", elapsed)
    qa = QABot(weather=weather, feed=SAMPLE_FEED, household=plan_from_scenario(scenario),
               out_dir=out_dir, clock=clock, take_photo=take_photo, songs=songs)
    style = shipped_style() if style == "shipped" else style
    return DialogueManager(qa, chitchat=shipped_chitchat(), style=style,
                           on_reply=reply_logger(out_dir / "dialogue.jsonl"),
                           min_confidence=load_speech_config().acting_confidence,
                           talk=shipped_talk(scenario.staff))


def chat_session(scenario_path: Path | None, default_scenario: Path, weather_path: Path | None,
                 feed: Path | None, out: Path
                 ) -> tuple[DialogueManager, dict[str, float] | None, Path | None]:
    """The manager of a ``companion chat`` session, with the scenario's drives and personality
    (Nones without ``scenario_path``). The household map and the camera come from the scenario,
    or from ``default_scenario`` when none is given; maps, photos and the reply log go to
    ``out``. Every file is checked before a model is loaded: one that cannot be read raises a
    :class:`~core.errors.UserError` naming it."""
    drives, personality, household, scenario_weather = None, None, None, None
    staff = False
    if scenario_path is not None:
        scenario = load_scenario(scenario_path)
        scenario_weather, staff = scenario.weather, scenario.staff
        drives, personality = scenario.robot.drives.model_dump(), scenario.personality
        household = plan_from_scenario(scenario)
    elif default_scenario.is_file():
        household = plan_from_scenario(load_scenario(default_scenario))
    if feed is not None:
        check_feed(feed)
    if weather_path:
        weather = load_weather(weather_path)
    elif scenario_weather is not None:
        weather = load_weather(scenario_weather.model_dump(exclude_none=True))
    else:
        weather = load_weather()
    qa = QABot(weather=weather, feed=feed or SAMPLE_FEED, household=household, out_dir=out,
               take_photo=scenario_camera(scenario_path or default_scenario, out))
    manager = DialogueManager(qa, chitchat=shipped_chitchat(), style=shipped_style(),
                              on_reply=reply_logger(out / "dialogue.jsonl"),
                              min_confidence=load_speech_config().acting_confidence,
                              talk=shipped_talk(staff))
    return manager, drives, personality


def robot_mood(drives: Mapping[str, float] | None = None,
               personality: Path | None = None) -> tuple[str, float, float]:
    """``(mood, v_mood, threshold)`` from eq. 3.6 with no encouragement and no emotion.

    ``drives`` defaults to all zero, the scenario default for ``robot.drives``.
    """
    h = Homeostasis(load_personality(personality))
    d = np.array([float((drives or {}).get(k, 0.0)) for k in DRIVES])
    v = float(h.mood_value(d, 0.0, 0.0))
    positive = bool(h.mood_positive(v))
    return ("positive" if positive else "negative"), v, h.personality.mood.threshold
