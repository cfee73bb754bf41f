"""The dialogue manager of a household run: the QA bot knows the scenario's household map and
weather, tells the scenario's time (its ``time_of_day`` in the home city's time zone, moved on
by the simulated seconds), takes photos with the robot's camera, and chit-chat replies come
from the shipped seq2seq model, restyled by the shipped mood style-transfer model."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

from dialogue.cli import reply_logger, shipped_chitchat, shipped_style
from dialogue.manager import DialogueManager
from dialogue.qa.bot import QABot, load_weather
from dialogue.qa.clock import scenario_clock
from dialogue.qa.home_map import plan_from_scenario
from dialogue.qa.news import SAMPLE_FEED
from dialogue.qa.places import lookup


def household_dialogue(scenario: Any, elapsed: Callable[[], float], out_dir: Path,
                       take_photo: Callable[[], str | Path] | None = None,
                       style: Any = "shipped") -> DialogueManager:
    """A manager for a run of ``scenario``; replies are appended to ``out_dir/dialogue.jsonl``.
    ``style``: a style-transfer model, None for none, or "shipped" for the shipped one."""
    weather = (load_weather(scenario.weather.model_dump(exclude_none=True))
               if scenario.weather is not None else load_weather())
    home = lookup(weather.home_city) if weather.home_city else None
    clock = scenario_clock(scenario.time_of_day, home.timezone if home else "UTC", elapsed)
    qa = QABot(weather=weather, feed=SAMPLE_FEED, household=plan_from_scenario(scenario),
               out_dir=out_dir, clock=clock, take_photo=take_photo)
    style = shipped_style() if style == "shipped" else style
    return DialogueManager(qa, chitchat=shipped_chitchat(), style=style,
                           on_reply=reply_logger(out_dir / "dialogue.jsonl"))
