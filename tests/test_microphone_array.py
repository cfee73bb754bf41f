"""The head's four microphones (sim/microphone_array.py, Acoustics.parts_at_array):
a voice reaches each at its own time, the room's reverberation and noise are diffuse, and a
TV across the room is heard reverberated, at the levels of the one-microphone rendering."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
from scipy.signal import coherence

from dialogue.speech.training.rooms import ROBOT_HEADING, living_room
from robot.audio import RATE, SPEED_OF_SOUND
from robot.voices import PEOPLE_VOICES, synthesise
from sim.microphone_array import MicrophoneArray
from sim.robot_config import load_robot_config
from sim.soundscape import noise_loops

ROOT = Path(__file__).resolve().parents[1]
ARRAY = MicrophoneArray(load_robot_config().acoustics.microphones, RATE)


def test_a_voice_ahead_reaches_the_front_microphones_first_by_the_heads_depth():
    # the head at the origin facing +y; front left (0) and rear left (2) 7 cm apart
    delays = ARRAY.delays((0.0, 3.0), (0.0, 0.0), math.pi / 2)
    assert math.isclose(delays[2] - delays[0], 0.07 / SPEED_OF_SOUND, rel_tol=1e-6)
    assert math.isclose(delays[1], delays[0], abs_tol=1e-9)
    # to its left, the left microphones come first; turning the head turns the delays
    left = ARRAY.delays((-3.0, 0.0), (0.0, 0.0), math.pi / 2)
    assert left[0] < left[1] and left[2] < left[3]
    # a fraction of a sample is kept: a click arrives where the delay says
    click = np.zeros(256)
    click[100] = 1.0
    shifted = ARRAY.delayed(click, np.array([0.0, 2.5 / RATE, -1.25 / RATE, 10 / RATE]))
    peaks = [np.sum(np.arange(256) * s ** 2) / np.sum(s ** 2) for s in shifted]
    assert np.allclose(peaks, [100.0, 102.5, 98.75, 110.0], atol=0.2)


def test_mixed_noise_is_as_coherent_as_a_diffuse_field_and_as_loud():
    independent = np.random.default_rng(0).normal(size=(4, 20 * RATE))
    mixed = ARRAY.diffuse(independent)
    assert np.allclose(mixed.std(axis=1), 1.0, atol=0.05)
    f, before = coherence(independent[0], independent[3], RATE, nperseg=512)
    _, after = coherence(mixed[0], mixed[3], RATE, nperseg=512)
    low, high = (f > 100) & (f < 300), (f > 4500) & (f < 5500)
    # front left and rear right: 9.9 cm apart; sinc(2 f d / c)^2 is 0.93-0.99 and ~0
    assert before[low].mean() < 0.05 and after[low].mean() > 0.85
    assert after[high].mean() < 0.1


def _at_array(noise: str, distance: float) -> tuple[np.ndarray, np.ndarray]:
    room, robot = living_room(8.0, 7.0, noise)
    samples, rate = synthesise("Could you tell me what time it is?", PEOPLE_VOICES[2])
    return room.parts_at_array(samples, rate, (robot[0], robot[1] + distance), robot,
                               ROBOT_HEADING, noise_loops(0), np.random.default_rng(1))


def test_the_tv_across_the_room_is_heard_reverberated_at_the_one_microphone_level():
    room, robot = living_room(8.0, 7.0, "tv")
    _, background = _at_array("tv", 1.0)
    _, quiet = _at_array("quiet", 1.0)
    tv = background - quiet                  # the same draws: the programme alone
    level = 100 + 20 * math.log10(tv[0].std() / 32768)
    cfg = room.cfg
    direct, reverberant, _ = room.paths(room.sources["tv"], robot, cfg.talker_directivity)
    expected = 60.0 + 10 * math.log10(10 ** (direct / 10) + 10 ** (reverberant / 10))
    assert abs(level - expected) < 1.0
    # reverberated: most of its energy is the diffuse field, so the microphones' copies of
    # it agree far less at high frequencies than the direct sound alone would (~1)
    f, agree = coherence(tv[0], tv[3], RATE, nperseg=512)
    assert agree[(f > 3000) & (f < 6000)].mean() < 0.5
    # each microphone records its own copy: four different channels, all about as loud
    assert background.shape[0] == 4 and not np.allclose(background[0], background[1])


def test_a_household_run_with_the_array_records_four_channels_the_recogniser_takes(tmp_path):
    """Tom, 1.5 m to the robot's left (world bearing 90 degrees), asks for a photo: the run
    hands the robot four channels and where its head faced, not where Tom stood; the
    recogniser makes out the words, and the beam places the voice."""
    from behaviours.sense import voice_bearing
    from dialogue.speech.recognizer import SpeechRecognizer
    from robot.geometry import wrap_angle
    from sim.scenario import Event, Say, Start, load_scenario
    from sim.simulation import Simulation

    base = load_scenario(ROOT / "worlds" / "living_room.yaml")   # the robot at (4.3, 2.6)
    tom = next(q for q in base.people if q.name == "Tom").model_copy(update={
        "start": Start(x=4.3, y=4.1, yaw=-90.0),
        "events": (Event(at=0.5, say=Say(text="Please take a photo of us.")),)})
    robot = tmp_path / "robot.yaml"
    robot.write_text("microphones:\n  array: true\n")
    blocks = []      # the line's recording, block by block as it is said
    with Simulation(base.model_copy(update={"people": (tom,)}), robot_config=robot) as sim:
        while sim.t < 8.0 and not (blocks and blocks[-1].ends):
            sim.step()
            blocks += sim.robot.microphones.recordings()
    assert len(blocks) > 10
    sound = dataclasses.replace(blocks[0],
                                audio=np.concatenate([b.audio for b in blocks], axis=-1))
    assert sound.audio.shape[0] == 4 and sound.bearing is None
    assert SpeechRecognizer().transcribe(sound.audio, sound.rate).direction is None
    heard = SpeechRecognizer(microphones=sim.robot.cfg.acoustics.microphones).transcribe(
        sound.audio, sound.rate)
    assert "photo" in heard.text
    bearing = voice_bearing(sound, heard)
    assert abs(math.degrees(wrap_angle(bearing - math.pi / 2))) < 10.0
