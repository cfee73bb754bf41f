"""The household's sound, as the simulation makes it: people's lines spoken in their voices,
carried to the robot's microphones (sim/acoustics.py) and recorded there as
:class:`robot.percepts.Sound`; people who say a line again when the robot asks.

What was said, to whom, and how loud it was at the robot is kept in :attr:`said` for
scoring a run (the run logs it as ``said`` events); the robot never reads it.
"""

from __future__ import annotations

import logging
import math
from collections import OrderedDict
from pathlib import Path
from typing import Any, Literal

import numpy as np

from robot.audio import RATE
from robot.percepts import SayEvent, Sound
from robot.speaker import speech_seconds, write_wav
from robot.voices import VoiceError, synthesise
from sim.acoustics import Acoustics, Wall
from sim.hearing import Microphones
from sim.robot import Robot
from sim.scenario import Scenario, voice_of
from sim.soundscape import noise_loops
from sim.world import World

log = logging.getLogger(__name__)
REPEAT_AFTER_S = 1.0     # a person asked to say a line again starts this long after
KEPT_LINES = 64          # lines remembered for repeating
Hearing = Literal["audio", "fast"]   # the voices carried and recognised, or only their levels
CLOSER_M = 1.2           # a person asked to come closer stops this far from the robot


def household_acoustics(scenario: Scenario, world: World, robot: Robot) -> Acoustics:
    """The acoustics of ``world``: its rooms, its solid walls (the floor plan's wall
    pieces) and the furniture that plays a programme."""
    walls = [Wall(f.x - f.half_x, f.y - f.half_y, f.x + f.half_x, f.y + f.half_y)
             for f in world.obstacles() if f.kind == "wall"]
    sources = {f.name: (f.x, f.y) for f in scenario.furniture}
    return Acoustics(robot.cfg.acoustics, scenario.rooms, walls, sources)


class HouseholdSound:
    """Turns said lines into the robot's recordings, one line at a time. With ``hearing``
    ``"fast"`` no voice is synthesised nor carried: an audible line comes with its words
    and the signal-to-noise ratio the acoustics give it (:class:`Sound`), for sweeps that
    need the household's behaviour, not its hearing."""

    def __init__(self, scenario: Scenario, world: World, robot: Robot,
                 voices_dir: Path | None = None, hearing: Hearing = "audio") -> None:
        self.scenario, self.world, self.robot = scenario, world, robot
        self.hearing = hearing
        self.acoustics = household_acoustics(scenario, world, robot)
        self.microphones = Microphones(robot.cfg.microphones, scenario.seed)
        self.voices_dir = voices_dir
        self.said: list[dict[str, Any]] = []      # for scoring only; the run drains it
        self._lines: OrderedDict[int, tuple[SayEvent, str]] = OrderedDict()
        self._voices: dict[tuple[str, str], tuple[np.ndarray, int]] = {}

    def _voice(self, text: str, person: str) -> tuple[np.ndarray, int] | None:
        voice = voice_of(self.scenario, person)
        key = (text, voice.model_dump_json())
        if key not in self._voices:
            try:
                self._voices[key] = synthesise(text, voice)
            except VoiceError as exc:
                log.warning("%s", exc)
                return None
            if len(self._voices) > KEPT_LINES:
                self._voices.pop(next(iter(self._voices)))
        return self._voices[key]

    def record(self, event: SayEvent, kind: str = "say") -> Sound | None:
        """The robot's recording of ``event`` (None: too faint to make a sound)."""
        line = self.microphones.number()
        self._lines[line] = (event, kind)
        while len(self._lines) > KEPT_LINES:
            self._lines.popitem(last=False)
        x, y, _ = self.robot.base.pose()
        here = (x, y)
        speaker = self.world.people_positions().get(event.person)
        at = (speaker.x, speaker.y) if speaker else here
        level = self.acoustics.speech_db(at, here)
        background = self.acoustics.background_db(here)
        audible = level >= background - self.microphones.cfg.audible_below_noise_db
        said = {"line": line, "person": event.person, "to": event.to, "how": kind,
                "text": event.text, "level_db": round(level, 1),
                "noise_db": round(float(background), 1), "audible": bool(audible),
                "bearing": round(math.atan2(at[1] - y, at[0] - x), 3),
                "ended": round(event.t + speech_seconds(event.text), 2)}   # when it ends
        self.said.append(said)
        if not audible:
            return None
        if self.hearing == "fast":
            return Sound(line, event.t, event.person, self.microphones.bearing(here, at),
                         np.zeros(0), RATE, self.robot.camera.heading(), words=event.text,
                         snr_db=float(level - background))
        if (voice := self._voice(event.text, event.person)) is None:
            return None
        said["ended"] = round(event.t + len(voice[0]) / voice[1], 2)   # as the voice says it
        loops, rng = noise_loops(self.scenario.seed), self.microphones.rng
        heading, array = self.robot.camera.heading(), self.microphones.cfg.array
        if array:
            audio = self.acoustics.at_array(*voice, at, here, heading, loops, rng)
        else:
            audio = self.acoustics.at_microphones(*voice, at, here, loops, rng)
        if self.voices_dir is not None:
            write_wav(self.voices_dir / f"line-{line:04d}.wav",
                      np.clip(np.round(audio), -32768, 32767).astype(np.int16), RATE)
        bearing = None if array else self.microphones.bearing(here, at)
        return Sound(line, event.t, event.person, bearing, audio, RATE, heading)

    def asked_again(self, line: int, t: float, closer: bool = False) -> SayEvent | None:
        """The robot asked for ``line`` again: the same words, said again after a moment,
        by a person who repeats when asked, once (None otherwise). Asked to come closer,
        they first walk up to the robot (:meth:`World.approach`) and say it on arriving."""
        event, kind = self._lines.get(line, (None, ""))
        if event is None or kind == "repeat":
            return None
        person = next((p for p in self.scenario.people if p.name == event.person), None)
        if person is None or not person.repeat_if_asked:
            return None
        x, y, _ = self.robot.base.pose()
        walk_s = self.world.approach(event.person, t, (x, y), CLOSER_M) if closer else 0.0
        return SayEvent(t + walk_s + REPEAT_AFTER_S, event.person, event.text, event.to)

