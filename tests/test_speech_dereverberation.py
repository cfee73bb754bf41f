"""Dereverberation of the head's four microphones (dialogue/speech/dereverberation.py): the
room's late reverberation goes, the voice stays, and the recogniser applies it only when its
settings say how."""

from __future__ import annotations

import numpy as np
import pytest

from app.core.config_files import ConfigError
from app.sim.soundscape import noise_loops
from app.sim.voices import PEOPLE_VOICES, synthesise
from dialogue.speech.config import DereverberationConfig, load_speech_config
from dialogue.speech.dereverberation import dereverberate
from dialogue.speech.recognizer import SpeechRecognizer
from dialogue.speech.training.rooms import ROBOT_HEADING, living_room

WPE = DereverberationConfig(taps=10, delay=3, iterations=1)
TAIL = 4000   # samples (0.25 s): the end of a recording, after the voice's direct sound


@pytest.fixture(scope="module")
def voice() -> np.ndarray:
    """A line said 3 m away in a quiet living room, the voice alone at each microphone."""
    room, robot = living_room(8.0, 7.0, "quiet")
    samples, rate = synthesise("Can you tell me the news this morning?", PEOPLE_VOICES[1])
    said, _ = room.parts_at_array(samples, rate, (robot[0] + 1.5, robot[1] + 2.6), robot,
                                  ROBOT_HEADING, noise_loops(0), np.random.default_rng(2))
    return said


def db(x: np.ndarray) -> float:
    return float(10 * np.log10((np.asarray(x) ** 2).sum()))


def test_the_late_reverberation_goes_and_the_voice_stays(voice):
    clean = dereverberate(voice, WPE)
    assert clean.shape == voice.shape
    # the room ringing on after the voice ended, against the whole recording
    before = db(voice[0, -TAIL:]) - db(voice[0])
    after = db(clean[0, -TAIL:]) - db(clean[0])
    assert after < before - 6.0
    assert abs(db(clean[0]) - db(voice[0])) < 3.0


def test_the_recogniser_takes_the_reverberation_out_only_when_configured(voice, tmp_path):
    cfg = tmp_path / "wpe.yaml"
    cfg.write_text("model:\n  dereverberation: {taps: 10, delay: 3, iterations: 1}\n")
    with_wpe = SpeechRecognizer(load_speech_config(cfg))
    plain = SpeechRecognizer()
    assert plain.cfg.model.dereverberation is None
    assert not np.allclose(with_wpe.one_channel(voice), plain.one_channel(voice))
    assert np.allclose(with_wpe.one_channel(voice[:1]), voice[0])   # one microphone: as it is


def test_settings_that_cannot_dereverberate_are_refused(tmp_path):
    cfg = tmp_path / "bad.yaml"
    cfg.write_text("model:\n  dereverberation: {taps: 0, delay: 3, iterations: 1}\n")
    with pytest.raises(ConfigError, match="taps"):
        load_speech_config(cfg)
