"""Adapting the acoustic model: the wheel's packed mixture weights read back, a small
adaptation run with SphinxTrain's real tools, and the recogniser loading its result."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import numpy as np
import pytest
from pocketsphinx import get_model_path
from test_speech_recognition import recorded

from dialogue.speech.config import SpeechConfig, SpeechModelError, load_speech_config
from dialogue.speech.engines import ACOUSTIC_FILES
from dialogue.speech.recognizer import SpeechRecognizer
from dialogue.speech.training.acoustic import (
    adapt_acoustic_model,
    adaptation_beam,
    adaptation_enhancer,
    adaptation_front_end,
    adaptation_lines,
    record,
)
from dialogue.speech.training.corpus import DEV_FILE, HELD_OUT_FILES, tsv_lines
from dialogue.speech.training.sphinx_files import read_sendump, write_s3_array
from dialogue.speech.training.train import evaluation_words
from dialogue.speech.wav import read_wav
from dialogue.speech.words import spoken_words
from robot.audio import RATE
from sim.robot_config import load_robot_config

ROOT = Path(__file__).resolve().parents[1]

WHEEL = Path(get_model_path()) / "en-us" / "en-us"


def test_the_wheels_mixture_weights_are_distributions_per_senone_and_stream():
    weights = read_sendump(WHEEL / "sendump")
    assert weights.shape == (5126, 3, 128)
    assert np.allclose(weights.sum(axis=2), 1.0)


def test_mixture_weights_written_and_packed_again_read_back_the_same(tmp_path):
    cfg = load_speech_config().adapt
    weights = read_sendump(WHEEL / "sendump")
    write_s3_array(tmp_path / "mixture_weights", weights)
    subprocess.run(["pocketsphinx_mdef_convert", "-text", str(WHEEL / "mdef"),
                    str(tmp_path / "mdef.txt")], check=True, capture_output=True)
    subprocess.run([str(cfg.sphinxtrain_dir / "mk_s2sendump"), "-pocketsphinx", "yes",
                    "-moddeffn", str(tmp_path / "mdef.txt"),
                    "-mixwfn", str(tmp_path / "mixture_weights"),
                    "-sendumpfn", str(tmp_path / "sendump")], check=True, capture_output=True)
    again = read_sendump(tmp_path / "sendump")
    big = weights > 1e-3   # quantisation: 1024 steps of log base 1.0001, about 11 % apart
    assert np.allclose(np.log(again[big]), np.log(weights[big]), atol=0.11)


def test_evaluation_lines_are_never_adaptation_lines():
    assert adaptation_lines(set(), set()) == []   # a dictionary without words passes none
    everything = adaptation_lines(set(), _dictionary())
    first = tuple(everything[0])
    assert first not in map(tuple, adaptation_lines({first}, _dictionary()))


def _dictionary() -> set[str]:
    text = (WHEEL.parent / "cmudict-en-us.dict").read_text()
    return {line.split(maxsplit=1)[0] for line in text.splitlines() if line}


def with_acoustic_model(folder: Path) -> SpeechConfig:
    """pocketsphinx, as it was adapted (from the enhancer's masked sound), with ``folder``'s
    acoustic model."""
    cfg = load_speech_config()
    return cfg.model_copy(update={"model": cfg.model.model_copy(
        update={"engine": "pocketsphinx", "mask_output": True, "acoustic_model": folder})})


@pytest.fixture(scope="module")
def adapted(tmp_path_factory) -> Path:
    cfg = load_speech_config().adapt.model_copy(update={"max_lines": 40, "copies": 1,
                                                        "iterations": 1})
    out = tmp_path_factory.mktemp("acoustic")
    figures = adapt_acoustic_model(cfg, set(), out)
    assert figures["recordings"] == 40
    return out


def test_a_small_adaptation_moves_the_model_and_the_recogniser_loads_it(adapted):
    for name in ACOUSTIC_FILES:
        assert (adapted / name).is_file()
    assert (adapted / "means").read_bytes() != (WHEEL / "means").read_bytes()
    cfg = with_acoustic_model(adapted)
    text = "what time is it"
    heard = SpeechRecognizer(cfg).transcribe(recorded(text))
    assert heard.text.split() == spoken_words(text)


def test_a_missing_acoustic_model_file_is_a_clear_error(adapted, tmp_path):
    for name in ACOUSTIC_FILES[:-1]:
        (tmp_path / name).write_bytes((adapted / name).read_bytes())
    cfg = with_acoustic_model(tmp_path)
    with pytest.raises(SpeechModelError, match="noisedict"):
        SpeechRecognizer(cfg)


def test_the_adaptations_recordings_pass_through_the_recognisers_enhancer(tmp_path):
    cfg = load_speech_config()
    on = cfg.model_copy(update={"adapt": cfg.adapt.model_copy(update={"enhanced": True})})
    enhancer = adaptation_enhancer(on)
    assert enhancer is not None and enhancer.power == cfg.model.mask_power
    off = cfg.model_copy(update={"adapt": cfg.adapt.model_copy(update={"enhanced": False})})
    assert adaptation_enhancer(off) is None
    adapt = cfg.adapt.model_copy(update={"copies": 1, "tv_share": 1.0})
    lines = [["what", "time", "is", "it"]]
    for folder, through in (("raw", None), ("enhanced", enhancer)):
        (tmp_path / folder).mkdir()
        record(lines, adapt, tmp_path / folder, through)
    raw, enhanced = (read_wav(tmp_path / folder / "c0_00000.wav")[0].astype(np.float64)
                     for folder in ("raw", "enhanced"))
    lead = int(load_robot_config().acoustics.lead_s * RATE)   # the TV alone, before the line
    assert _db(enhanced[:lead]) < _db(raw[:lead]) - 10.0


def test_the_adaptation_can_record_the_heads_microphones_and_take_them_through_the_beam(
        tmp_path):
    cfg = load_speech_config()
    assert cfg.adapt.array and cfg.model.beamformer      # shipped: through the beam
    assert adaptation_beam(cfg) is not None
    one = cfg.model_copy(update={"adapt": cfg.adapt.model_copy(update={"array": False})})
    assert adaptation_beam(one) is None
    # what the recordings passed through is recorded with the model, the shipped one's too
    assert adaptation_front_end(cfg)["dereverberation"] == cfg.model.dereverberation.model_dump()
    assert adaptation_front_end(one)["beam"] is False
    shipped = json.loads((ROOT / "assets/models/speech/acoustic/adaptation.json").read_text())
    assert shipped["front_end"] == adaptation_front_end(cfg)
    adapt = cfg.adapt.model_copy(update={"copies": 1, "tv_share": 1.0, "array": True})
    lines = [["what", "time", "is", "it"]]
    heard: list[np.ndarray] = []

    def beam(heads: np.ndarray) -> np.ndarray:   # records what it is given, passes the rear
        heard.append(heads)
        return heads[3]

    record(lines, adapt, tmp_path, beam=beam)
    written = read_wav(tmp_path / "c0_00000.wav")[0]
    assert heard[0].shape[0] == 4
    assert np.array_equal(written, np.clip(np.round(heard[0][3]), -32768, 32767))


def _db(x: np.ndarray) -> float:
    return 10.0 * float(np.log10(np.mean(x ** 2) + 1e-9))


def test_the_requests_settings_are_chosen_on_are_learnt_by_no_model_nor_evaluated():
    requests = {tuple(spoken_words(text)) for _, text in tsv_lines(DEV_FILE)}
    assert len(requests) == 90
    assert requests <= evaluation_words()   # left out of the language model's corpus
    training = {tuple(words) for words in adaptation_lines(set(), _dictionary())}
    assert not requests & training          # nor said to the acoustic model or the enhancer
    held_out = {tuple(spoken_words(text)) for name in HELD_OUT_FILES
                for _, text in tsv_lines(name)}
    assert not requests & held_out          # nor among eval asr's lines
