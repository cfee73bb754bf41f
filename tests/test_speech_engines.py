"""The recogniser's decoders: faster-whisper on the Whisper model inside its wheel makes out
a voice of a synthesizer family no setting was chosen on, with the network out of reach;
both decoders sit behind the same recogniser interface."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import jiwer
import numpy as np
import pytest

from dialogue.speech.config import load_speech_config
from dialogue.speech.recognizer import SpeechRecognizer
from dialogue.speech.words import spoken_words

ROOT = Path(__file__).resolve().parents[1]
LINE = "Could you tell me the current time in Cairo?"

OFFLINE = """
import json, socket, sys
def refuse(*args, **kwargs):
    raise OSError("no network in this test")
socket.socket.connect = refuse
socket.create_connection = refuse
from dialogue.speech.config import load_speech_config
from dialogue.speech.recognizer import SpeechRecognizer
from robot.audio import resampled
from robot.voices import Voice, synthesise
cfg = load_speech_config()
cfg = cfg.model_copy(update={"model": cfg.model.model_copy(update={"engine": "whisper"})})
samples, rate = synthesise(sys.argv[1], Voice(engine="flite", name="slt", speed=135))
heard = SpeechRecognizer(cfg).transcribe(resampled(samples.astype(float), rate))
print(json.dumps({"text": heard.text, "confidence": heard.confidence}))
"""


def test_whisper_hears_a_held_out_voice_with_the_network_and_the_hub_out_of_reach():
    env = {"PATH": "/usr/bin:/bin", "HF_ENDPOINT": "http://127.0.0.1:9",
           "HF_HUB_OFFLINE": "1", "HOME": "/nonexistent"}
    done = subprocess.run([sys.executable, "-c", OFFLINE, LINE], cwd=ROOT, env=env,
                          capture_output=True, text=True, timeout=300, check=True)
    heard = json.loads(done.stdout.strip().splitlines()[-1])
    ref = " ".join(spoken_words(LINE))
    words_wrong = jiwer.process_words(ref, heard["text"])
    assert words_wrong.substitutions + words_wrong.deletions + words_wrong.insertions <= 1
    assert heard["confidence"] > 0.5


@pytest.mark.parametrize("engine", ["whisper", "pocketsphinx"])
def test_either_decoder_gives_nothing_for_silence_and_a_threshold_of_its_own(engine):
    cfg = load_speech_config()
    cfg = cfg.model_copy(update={"model": cfg.model.model_copy(update={"engine": engine})})
    recogniser = SpeechRecognizer(cfg)
    heard = recogniser.transcribe(np.zeros(16000))
    assert heard.text == "" and not recogniser.understood(heard)
    own = cfg.model.whisper.min_confidence if engine == "whisper" else cfg.min_confidence
    assert recogniser.min_confidence == own
