"""The voice-activity detector (dialogue/speech/vad.py): Silero VAD from the faster-whisper
wheel on lines said by the project's voices, padded with silence, fed as a microphone feeds
it; where each utterance starts and ends, how soon its end is known, and what is not one."""

from __future__ import annotations

import numpy as np
import pytest

from core.config_files import ConfigError
from dialogue.speech.config import load_speech_config
from dialogue.speech.vad import SpeechStart, Utterance, UtteranceDetector, speech_present
from robot.audio import RATE, resampled
from robot.voices import PEOPLE_VOICES, Voice, synthesise

BLOCK = 480                     # 30 ms, as the microphone gives them
TOLERANCE_S = 0.3
CFG = load_speech_config().vad


def said(text: str, voice: Voice = PEOPLE_VOICES[0]) -> tuple[np.ndarray, int, int]:
    """``text`` at 16 kHz and where its sound begins and ends (samples over 1 % of full
    scale)."""
    samples, rate = synthesise(text, voice)
    x = resampled(samples, rate)
    loud = np.flatnonzero(np.abs(x) > 330)
    return x, int(loud[0]), int(loud[-1])


def quiet(seconds: float, rms: float = 0.0, seed: int = 0) -> np.ndarray:
    """``seconds`` of silence, or of white noise of ``rms`` (int16 scale)."""
    n = round(seconds * RATE)
    return np.random.default_rng(seed).normal(0.0, rms, n) if rms else np.zeros(n)


def int16(x: np.ndarray) -> np.ndarray:
    return np.clip(np.round(x), -32768, 32767).astype(np.int16)


@pytest.fixture(scope="module")
def two_lines() -> tuple[np.ndarray, list[tuple[float, float]]]:
    """Two lines (an espeak-ng and a Flite voice), 1 s of silence before, between and
    after, over a faint hiss; and where each line's sound is, in seconds."""
    parts, truth, at = [quiet(1.0)], [], RATE
    for text, voice in (("Where is the kitchen?", PEOPLE_VOICES[0]),
                        ("What time is it in Paris?", Voice(engine="flite", name="slt"))):
        x, a, b = said(text, voice)
        truth.append(((at + a) / RATE, (at + b) / RATE))
        parts += [x, quiet(1.0)]
        at += len(x) + RATE
    x = np.concatenate(parts)
    return int16(x + quiet(len(x) / RATE, rms=20.0)), truth


def stream(samples: np.ndarray, block: int = BLOCK, detector: UtteranceDetector | None = None
           ) -> list[tuple[SpeechStart | Utterance, int]]:
    """Each event of ``samples`` fed in blocks, with how many samples had been fed then."""
    detector = detector or UtteranceDetector()
    events = []
    for i in range(0, len(samples), block):
        events += [(e, detector.fed) for e in detector.feed(samples[i:i + block])]
    return events + [(e, detector.fed) for e in detector.finish()]


def spoken(events: list) -> list[Utterance]:
    return [e for e, _ in events if isinstance(e, Utterance)]


def test_each_line_is_one_utterance_that_starts_and_ends_where_the_line_does(two_lines):
    samples, truth = two_lines
    found = spoken(stream(samples))
    assert len(found) == 2
    for u, (start, end) in zip(found, truth, strict=True):
        assert abs(u.start_s - start) <= TOLERANCE_S, (u.start_s, start)
        assert abs(u.end_s - end) <= TOLERANCE_S, (u.end_s, end)


def test_an_utterance_ends_after_the_minimum_silence_while_silence_is_still_fed(two_lines):
    samples, truth = two_lines
    events = stream(samples)
    for (u, fed), (_, end) in zip([(e, f) for e, f in events if isinstance(e, Utterance)],
                                  truth, strict=True):
        waited = u.decided / RATE - end
        assert CFG.min_silence_ms / 1000 <= waited <= CFG.min_silence_ms / 1000 + 0.2, waited
        assert fed < len(samples) and fed - u.decided < BLOCK + 512   # not at the input's end


def test_each_start_is_reported_once_it_has_lasted_the_minimum_speech(two_lines):
    samples, _ = two_lines
    events = stream(samples)
    kinds = [type(e).__name__ for e, _ in events]
    assert kinds == ["SpeechStart", "Utterance", "SpeechStart", "Utterance"]
    for (start, fed), (u, _) in zip(events[::2], events[1::2], strict=True):
        assert start.start == u.start
        assert CFG.min_speech_ms / 1000 <= (fed - start.start) / RATE <= 0.5


def test_the_utterance_keeps_the_pre_roll_before_its_start_and_after_its_end(two_lines):
    samples, _ = two_lines
    u = spoken(stream(samples))[0]
    pad = CFG.pre_roll_ms * RATE // 1000
    np.testing.assert_array_equal(u.samples, samples[u.start - pad:u.end + pad])


def test_blocks_of_any_length_give_the_same_utterances(two_lines):
    samples, _ = two_lines
    spans = {block: [(u.start, u.end) for u in spoken(stream(samples, block))]
             for block in (100, BLOCK, 512, 7_000)}
    assert len(set(map(tuple, spans.values()))) == 1, spans


def test_the_detector_says_when_someone_is_speaking(two_lines):
    samples, (first, _) = two_lines
    detector = UtteranceDetector()
    middle = round((first[0] + first[1]) / 2 * RATE)
    detector.feed(samples[:middle])
    assert detector.speaking
    detector.feed(samples[middle:round((first[1] + CFG.min_silence_ms / 1000 + 0.15) * RATE)])
    assert not detector.speaking


@pytest.mark.parametrize("rms", [0.0, 30.0, 150.0], ids=["silence", "hiss", "noise"])
def test_silence_and_low_noise_are_no_utterance_and_no_speech(rms):
    samples = int16(quiet(4.0, rms=rms, seed=1))
    assert stream(samples) == []
    assert not speech_present(samples[-RATE // 2:], CFG)


def test_speech_present_in_half_a_second_of_a_line():
    x, a, _ = said("Can you sing a song for me?")
    assert speech_present(int16(x[a:a + RATE // 2]), CFG)


def test_speech_longer_than_the_longest_utterance_is_ended_there():
    x, a, _ = said("Tell me about the weather in London and in Paris today, please, and "
                   "what the news is.")
    cfg = CFG.model_copy(update={"max_utterance_s": 1.0})
    found = spoken(stream(int16(np.concatenate([quiet(0.5), x, quiet(1.0)])),
                          detector=UtteranceDetector(cfg)))
    assert len(found) >= 2
    assert abs(found[0].start - (RATE // 2 + a)) <= TOLERANCE_S * RATE
    assert all(u.end - u.start <= RATE + 512 for u in found)


def test_vad_settings_out_of_range_are_refused_with_their_path(tmp_path):
    bad = tmp_path / "speech.yaml"
    bad.write_text("vad: {threshold: 1.5}\n")
    with pytest.raises(ConfigError, match=r"vad\.threshold"):
        load_speech_config(bad)
