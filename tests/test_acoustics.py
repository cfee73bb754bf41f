"""Room acoustics (sim/acoustics.py): distance, walls, doors, noise and what the
recorded voice sounds like."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pybullet as p
import pytest

from dialogue.speech.config import load_speech_config
from dialogue.speech.recognizer import SpeechRecognizer
from robot.audio import RATE
from robot.voices import PEOPLE_VOICES, synthesise
from sim.acoustics import Acoustics, Wall
from sim.layout import Room
from sim.robot_config import load_robot_config
from sim.scenario import load_scenario
from sim.soundscape import noise_loops
from sim.world import World

ROOT = Path(__file__).resolve().parents[1]
CFG = load_robot_config().acoustics
SPEECH = load_speech_config()


def one_room(**noise) -> Acoustics:
    return Acoustics(CFG, [Room(name="r", x=(0.0, 8.0), y=(0.0, 6.0), **noise)], [], {})


def background(a: Acoustics, at: tuple[float, float]) -> float:
    return a.background_db(at)


def test_the_direct_sound_loses_six_decibels_a_doubling_of_distance():
    a = one_room()
    assert a.paths((1.0, 1.0), (3.0, 1.0))[0] - a.paths((1.0, 1.0), (5.0, 1.0))[0] \
        == pytest.approx(20 * math.log10(2), abs=1e-6)


def test_a_wall_in_the_way_takes_its_loss_and_an_open_door_lets_sound_round():
    rooms = [Room(name="a", x=(0.0, 4.0), y=(0.0, 4.0)),
             Room(name="b", x=(4.0, 8.0), y=(0.0, 4.0),
                  doors=({"name": "d", "wall": "west", "offset": 3.5, "width": 0.9},))]
    a = Acoustics(CFG, rooms, [Wall(3.95, 0.0, 4.05, 3.05)], {})
    assert a.walls_between((2.0, 1.0), (6.0, 1.0)) == 1
    assert a.walls_between((2.0, 3.5), (6.0, 3.5)) == 0      # straight through the doorway
    through_wall = -20 * math.log10(4.0) - CFG.wall_loss_db
    assert a.paths((2.0, 1.0), (6.0, 1.0))[0] > through_wall + 10   # round by the door


def test_a_line_said_eight_metres_away_behind_a_wall_is_not_heard():
    """The nursing home: someone at the far end of the corridor, the robot deep in the
    lounge, a wall between them and the lounge door far off. Only the corridor's echo
    leaks through the door: too faint for the recogniser to take for speech."""
    scenario = load_scenario(ROOT / "worlds" / "nursing_home.yaml")
    client = p.connect(p.DIRECT)
    try:
        world = World(scenario, client)
        walls = [Wall(f.x - f.half_x, f.y - f.half_y, f.x + f.half_x, f.y + f.half_y)
                 for f in world.obstacles() if f.kind == "wall"]
    finally:
        p.disconnect(client)
    a = Acoustics(CFG, scenario.rooms, walls, {f.name: (f.x, f.y) for f in scenario.furniture})
    speaker, robot = (0.6, -1.2), (7.5, 3.0)
    assert math.dist(speaker, robot) >= 8.0 and a.walls_between(speaker, robot) >= 1
    assert a.speech_db(speaker, robot) < SPEECH.min_level_db
    samples, rate = synthesise("What time is it?", PEOPLE_VOICES[1])
    audio = a.at_microphones(samples, rate, speaker, robot, noise_loops(0),
                             np.random.default_rng(0))
    assert SpeechRecognizer().transcribe(audio, RATE).text == ""
    near = (6.5, 3.0)
    assert a.speech_db(near, robot) > background(a, robot) + 15


def test_the_tv_drowns_a_voice_from_across_the_room_more_than_one_close_by():
    a = one_room(noise={"source": "tv", "source_db": 65.0})
    a.sources["tv"] = (4.0, 5.8)
    quiet = one_room()
    assert background(a, (4.0, 1.0)) > background(quiet, (4.0, 1.0)) + 10
    near = a.speech_db((4.0, 2.0), (4.0, 1.0)) - background(a, (4.0, 1.0))
    far = a.speech_db((4.0, 5.0), (4.0, 1.0)) - background(a, (4.0, 1.0))
    assert near > far


def test_the_recording_holds_the_room_before_the_voice_and_the_voice_at_its_level():
    samples, rate = synthesise("Hello there", PEOPLE_VOICES[0])
    a = one_room()
    audio = a.at_microphones(samples, rate, (4.0, 2.0), (4.0, 1.0), noise_loops(0),
                             np.random.default_rng(0))
    lead = int(CFG.lead_s * RATE)
    rms = float(np.sqrt((audio[:lead] ** 2).mean()))
    level = 100 + 20 * math.log10(rms / 32768)
    assert level == pytest.approx(background(a, (4.0, 1.0)), abs=1.5)
    voiced = audio[lead:lead + int(0.8 * len(samples) * RATE / rate)]
    assert 20 * math.log10(float(np.sqrt((voiced ** 2).mean())) / rms) > 15
