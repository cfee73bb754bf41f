"""Voices from espeak-ng in process: people sound unlike each other, unknown voices are
refused with the scenario named, and a run with audio speaks the robot's sentences and the
people's lines into WAV files."""

from __future__ import annotations

import json
import subprocess
import sys
import wave
from pathlib import Path

import numpy as np
import pytest
import yaml

from app.run import RunOptions, prepare_scenario, run_scenario
from core.config_files import ConfigError
from robot.voices import PEOPLE_VOICES, Voice, synthesise
from sim.scenario import load_scenario, voice_of

ROOT = Path(__file__).resolve().parents[1]


def median_pitch(samples: np.ndarray, rate: int) -> float:
    """Median fundamental frequency (Hz) of the voiced 40-ms frames, by autocorrelation."""
    x = samples.astype(np.float64)
    size, pitches = int(0.04 * rate), []
    lags = np.arange(rate // 400, rate // 60)
    for start in range(0, len(x) - size, size):
        frame = x[start:start + size] - x[start:start + size].mean()
        energy = float(frame @ frame)
        if energy < 1e6 * size:            # silence between words
            continue
        corr = np.array([frame[:-lag] @ frame[lag:] for lag in lags]) / energy
        if corr.max() > 0.5:
            pitches.append(rate / lags[int(corr.argmax())])
    return float(np.median(pitches))


def test_voices_differ_in_pitch_and_length_follows_speed() -> None:
    text = "Good morning, would you like to hear the news today?"
    high = median_pitch(*synthesise(text, Voice(name="en-us", variant="f3", pitch=70)))
    low = median_pitch(*synthesise(text, Voice(name="en-us", variant="m3", pitch=30)))
    assert high > 1.4 * low
    slow, rate = synthesise(text, Voice(speed=100))
    fast, _ = synthesise(text, Voice(speed=200))
    assert 1.6 < len(slow) / len(fast) < 2.4
    assert 2.0 < len(fast) / rate < 4.5


def test_each_person_gets_a_voice_of_their_own() -> None:
    scenario = load_scenario(ROOT / "worlds" / "nursing_home.yaml")
    voices = [voice_of(scenario, p.name) for p in scenario.people]
    assert len({(v.label, v.pitch, v.speed) for v in voices}) == len(voices)
    assert voices[0] == PEOPLE_VOICES[0]


def test_an_unknown_voice_is_refused_with_its_place(tmp_path) -> None:
    data = yaml.safe_load((ROOT / "worlds" / "living_room.yaml").read_text())
    data.pop("personality", None)
    data["people"][1]["voice"] = {"name": "xx-nowhere", "pitch": 40}
    path = tmp_path / "w.yaml"
    path.write_text(yaml.safe_dump(data))
    with pytest.raises(ConfigError, match=r"people\[1\]\.voice: espeak-ng has no voice"):
        load_scenario(path)
    data["people"][1]["voice"] = {"name": "en; rm -rf"}
    path.write_text(yaml.safe_dump(data))
    with pytest.raises(ConfigError, match=r"people\[1\]\.voice\.name"):
        load_scenario(path)


def test_a_run_with_audio_speaks_the_robot_and_the_people(tmp_path) -> None:
    data = yaml.safe_load((ROOT / "worlds" / "living_room.yaml").read_text())
    data.pop("personality", None)
    grace = data["people"][0]
    grace["events"] = [{"at": 1, "say": "Hello robot, what time is it?"}]
    for person in data["people"][1:]:
        person["events"] = []
    path = tmp_path / "w.yaml"
    path.write_text(yaml.safe_dump(data))
    out = tmp_path / "run"
    run_scenario(prepare_scenario(path, duration=12), out, RunOptions(audio=True, adapt=False),
                 progress=False)
    events = [json.loads(line) for line in (out / "events.jsonl").open()]
    said = [e for e in events if e["kind"] == "say" and e.get("to") == grace["name"]]
    assert said and all((out / "audio" / e["audio"]).is_file() for e in said)
    heard = next(e for e in events if e["kind"] == "heard")
    line = out / "audio" / "people" / f"line-{heard['line']:04d}.wav"
    with wave.open(str(line)) as w:
        assert w.getnframes() / w.getframerate() > 1.0


SAY_TWICE = """
import hashlib
from sim.soundscape import noise_loops
from robot.voices import PEOPLE_VOICES, synthesise
noise_loops(0)   # the TV's presenter first, as a household run does
for voice in PEOPLE_VOICES:
    samples, rate = synthesise("Where is the kitchen?", voice)
    print(hashlib.md5(samples.tobytes() + str(rate).encode()).hexdigest())
"""


def test_the_same_lines_said_in_a_fresh_process_sound_the_same_every_time() -> None:
    """espeak-ng's breathy and Klatt voices draw noise; seeded before each line, a run that
    says the same lines in the same order is repeated sample for sample."""
    said = [subprocess.run([sys.executable, "-c", SAY_TWICE], cwd=ROOT, check=True,
                           capture_output=True, text=True).stdout for _ in range(2)]
    assert said[0] == said[1] and len(set(said[0].split())) == len(PEOPLE_VOICES)


def test_a_line_sounds_the_same_whatever_was_said_before_it() -> None:
    """espeak-ng carries state from one sentence to the next that its API cannot reset;
    loaded afresh for each line, the same line in the same voice is the same samples after
    any other lines, so a test or a run does not depend on what the process said first."""
    line = "What time is it in New York right now?"
    first = synthesise(line, PEOPLE_VOICES[1])[0]
    for voice in PEOPLE_VOICES:
        synthesise("Can you sing Happy Birthday for me?", voice)
    assert np.array_equal(synthesise(line, PEOPLE_VOICES[1])[0], first)


@pytest.mark.parametrize("voice", [Voice(engine="piper", name="joe"),
                                   Voice(engine="flite", name="slt"),
                                   Voice(engine="festival", name="kal_diphone")],
                         ids=lambda v: v.label)
def test_the_other_engines_speak_the_same_line_the_same_way_at_their_pace(voice) -> None:
    """Piper (its noise terms off), Flite and Festival: a line is the same samples each
    time, and a slower speed makes it longer."""
    line = "Is it morning or night in Melbourne right now?"
    first, rate = synthesise(line, voice)
    assert np.array_equal(synthesise(line, voice)[0], first)
    assert 1.5 < len(first) / rate < 6.0
    slow, _ = synthesise(line, voice.model_copy(update={"speed": 100}))
    assert len(slow) > 1.2 * len(first)


def test_a_voice_an_engine_lacks_or_espeak_settings_elsewhere_are_refused_by_name() -> None:
    with pytest.raises(ValueError, match="flite has no voice 'bob'"):
        Voice(engine="flite", name="bob")
    with pytest.raises(ValueError, match="variant and pitch are espeak-ng's"):
        Voice(engine="piper", name="joe", pitch=70)
    with pytest.raises(ValueError, match="tract is Piper's"):
        Voice(name="en-us", tract=1.1)


def test_a_shorter_vocal_tract_raises_piper_s_voice_and_keeps_its_pace() -> None:
    line = "Good morning, is my daughter coming today?"
    own, own_rate = synthesise(line, Voice(engine="piper", name="joe"))
    small, small_rate = synthesise(line, Voice(engine="piper", name="joe", tract=1.18))
    assert 1.12 < median_pitch(small, small_rate) / median_pitch(own, own_rate) < 1.25
    assert 0.9 < (len(small) / small_rate) / (len(own) / own_rate) < 1.1
    assert small_rate % 400 == 0
