"""Where a voice ends, from the microphones' blocks: an utterance is handed on for
recognition once its speech has been followed by the detector's silence, while the
recording goes on, not when the recording (or a fixed wait) ends."""

from __future__ import annotations

import dataclasses

import numpy as np

from behaviours.voice_streams import VoiceStreams
from dialogue.speech.config import load_speech_config
from robot.audio import RATE, resampled
from robot.percepts import Sound
from robot.voices import PEOPLE_VOICES, synthesise
from sim.inputs import SimMicrophones

TICK = 0.1   # s: the scenarios' step, at which Sense takes the microphones' blocks


def recording(text: str, after_s: float) -> tuple[Sound, float]:
    """``text`` said from 0.5 s into a recording that goes on ``after_s`` past the voice
    (a little noise throughout), and where the voice ends (s)."""
    samples, rate = synthesise(text, PEOPLE_VOICES[0])
    voice = resampled(samples, rate)
    audio = np.concatenate([np.zeros(RATE // 2), voice, np.zeros(round(after_s * RATE))])
    audio += np.random.default_rng(0).normal(0.0, 20.0, len(audio))
    return Sound(1, 0.5, "Tom", None, audio, RATE, 0.0), 0.5 + len(voice) / RATE


def test_an_utterance_is_handed_on_once_the_voice_has_stopped_not_when_the_recording_ends():
    sound, voice_end = recording("What is the weather like in Paris today?", after_s=3.0)
    microphones, streams = SimMicrophones(), VoiceStreams(load_speech_config().vad)
    microphones.record(sound, begins=0.0)
    started, handed = None, []
    for k in range(1, round((voice_end + 3.0) / TICK) + 2):
        microphones.advance(k * TICK)
        for block in microphones.recordings():
            heard = streams.take(block)
            if heard.started and started is None:
                started = k * TICK
            handed += [(k * TICK, u) for u in heard.utterances]
            if heard.utterances:
                streams.made_out(block.line)      # as Sense does when words came of it
    assert started is not None and 0.5 < started < 1.0
    (at, utterance), = handed
    # the synthesised voice ends in a little silence of its own; the recording goes on 3 s
    assert voice_end + 0.2 < at < voice_end + 0.9
    assert utterance.audio.shape[-1] < sound.audio.shape[-1]
    assert np.array_equal(utterance.audio, sound.audio[:utterance.audio.shape[-1]])


def test_a_recording_without_speech_is_handed_on_whole_when_it_ends():
    """No voice the detector finds (a faint one, or none): the recogniser judges it."""
    noise = np.random.default_rng(1).normal(0.0, 20.0, 2 * RATE)
    streams = VoiceStreams(load_speech_config().vad)
    first = streams.take(Sound(3, 0.0, "Ann", None, noise[:RATE], RATE, 0.0, ends=False))
    last = streams.take(Sound(3, 0.0, "Ann", None, noise[RATE:], RATE, 0.0))
    assert not first.started and first.utterances == [] and not last.started
    assert len(last.utterances) == 1 and np.array_equal(last.utterances[0].audio, noise)


def test_a_faint_voice_nothing_was_made_out_of_is_judged_whole_when_it_ends():
    """The detector may cut a faint voice into fragments the recogniser gets no words from;
    then the whole recording is recognised once it ends. Once words were made out, the
    rest of the recording is not handed on again."""
    sound, _ = recording("Could you play something calm for me?", after_s=2.0)
    half = sound.audio.shape[-1] // 2
    for made_out, whole in ((False, True), (True, False)):
        streams = VoiceStreams(load_speech_config().vad)
        streams.take(dataclasses.replace(sound, audio=sound.audio[:half], ends=False))
        if made_out:
            streams.made_out(sound.line)
        last = streams.take(dataclasses.replace(sound, audio=sound.audio[half:]))
        assert (len(last.utterances) == 1
                and np.array_equal(last.utterances[0].audio, sound.audio)) == whole
