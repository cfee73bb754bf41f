"""Dereverberation of the head's four microphones (dialogue/speech/dereverberation.py): the
room's reverberation goes, the voice stays, and the recogniser applies it only when its
settings say how (as shipped they do)."""

from __future__ import annotations

import numpy as np
import pytest

from core.config_files import ConfigError
from dialogue.speech.config import DereverberationConfig, load_speech_config
from dialogue.speech.dereverberation import dereverberate
from dialogue.speech.recognizer import SpeechRecognizer
from dialogue.speech.training.rooms import ROBOT_HEADING, living_room
from robot.voices import PEOPLE_VOICES, synthesise
from sim.acoustics import Acoustics
from sim.robot_config import load_robot_config
from sim.soundscape import noise_loops

WPE = DereverberationConfig(taps=10, delay=3, iterations=1)
LINE = "Can you tell me the news this morning?"


def recorded(absorption: float) -> np.ndarray:
    """The line said 3 m away in a quiet living room whose surfaces absorb ``absorption``
    of the sound: the voice alone at each microphone."""
    room, robot = living_room(8.0, 7.0, "quiet")
    room = Acoustics(room.cfg.model_copy(update={"absorption": absorption}), room.rooms,
                     room.walls, room.sources)
    samples, rate = synthesise(LINE, PEOPLE_VOICES[1])
    said, _ = room.parts_at_array(samples, rate, (robot[0] + 1.5, robot[1] + 2.6), robot,
                                  ROBOT_HEADING, noise_loops(0), np.random.default_rng(2))
    return said


@pytest.fixture(scope="module")
def voice() -> np.ndarray:
    """The line in the furnished room (robot.yaml's absorption)."""
    return recorded(load_robot_config().acoustics.absorption)


def direct_over_rest_db(x: np.ndarray, direct: np.ndarray) -> float:
    """How far the best-scaled ``direct`` sound stands above what else is in ``x``."""
    n = min(len(x), len(direct))
    x, direct = x[:n], direct[:n]
    gain = (x @ direct) / (direct @ direct)
    rest = x - gain * direct
    return float(10 * np.log10(gain ** 2 * (direct @ direct) / (rest @ rest)))


def test_the_reverberation_goes_and_the_voice_stays(voice):
    direct = recorded(0.99)[0]   # a room that returns almost nothing: the direct sound
    clean = dereverberate(voice, WPE)
    assert clean.shape == voice.shape
    before = direct_over_rest_db(voice[0], direct)
    after = direct_over_rest_db(clean[0], direct)
    assert after > before + 4.0   # 4.1 -> 10.7 dB when written
    level = 10 * np.log10((clean[0] ** 2).sum() / (voice[0] ** 2).sum())
    assert abs(level) < 3.0


def test_the_recogniser_takes_the_reverberation_out_only_when_configured(voice, tmp_path):
    cfg = tmp_path / "plain.yaml"
    cfg.write_text("model:\n  dereverberation: null\n")
    plain = SpeechRecognizer(load_speech_config(cfg))
    shipped = SpeechRecognizer()
    assert shipped.cfg.model.dereverberation == WPE          # shipped: on
    assert not np.allclose(shipped.one_channel(voice), plain.one_channel(voice))
    assert np.allclose(shipped.one_channel(voice[:1]), voice[0])   # one microphone: as it is


def test_settings_that_cannot_dereverberate_are_refused(tmp_path):
    cfg = tmp_path / "bad.yaml"
    cfg.write_text("model:\n  dereverberation: {taps: 0, delay: 3, iterations: 1}\n")
    with pytest.raises(ConfigError, match="taps"):
        load_speech_config(cfg)
