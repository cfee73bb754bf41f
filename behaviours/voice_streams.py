"""Where each voice starts and ends, from the microphones' blocks (robot/body.py).

The microphones hand on each line's recording block by block while it is said. A
voice-activity detector (:class:`dialogue.speech.vad.UtteranceDetector`, Silero VAD) on
each recording's first channel says when speech has started in it, which is when the robot
is being spoken over, and when an utterance has ended (speech, then ``min_silence_ms`` of
silence), which is when the robot may answer. Each ended utterance is handed on as one
:class:`~robot.percepts.Sound` of all the channels from where the last one ended (the
recording's start for the first, so its lead, the noise before the voice, comes too) to where
the detector decided. A recording that ends in speech ends its utterance there. One of which
no utterance was made out (:meth:`VoiceStreams.made_out`: the detector found no speech, or
only fragments of a faint voice the recogniser got no words from) is handed on whole once
it ends, for the recogniser to judge as one sound (too faint, or a voice the detector
missed); the robot responds to a voice of which nothing was made out
(:attr:`Heard.whole`, :attr:`Heard.voiced`) only then, once.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from dialogue.speech.config import VadConfig
from dialogue.speech.vad import SpeechStart, Utterance, UtteranceDetector
from robot.audio import RATE
from robot.percepts import Sound


@dataclasses.dataclass
class _Stream:
    sound: Sound                 # its first block: who said it, when, where the head faced
    blocks: list[np.ndarray]     # every block so far, each (M, n) or (n,)
    detector: UtteranceDetector
    fed: int = 0                 # samples so far
    handed: int = 0              # samples already handed on in utterances
    made_out: bool = False       # words were recognised in one of them
    voiced: bool = False         # the detector found speech in it


@dataclasses.dataclass(frozen=True)
class Heard:
    """What one block completed: whether speech started in it (``started``), and the
    utterances it ended, each a whole :class:`Sound`; ``whole``: the recording ended with
    nothing made out of it, and its one utterance is all of it; ``voiced``: the detector
    found speech in that recording."""

    started: bool
    utterances: list[Sound]
    whole: bool = False
    voiced: bool = False


class VoiceStreams:
    """One detector per recording, fed block by block (:meth:`take`)."""

    def __init__(self, cfg: VadConfig) -> None:
        self.cfg = cfg
        self._streams: dict[int, _Stream] = {}

    def take(self, block: Sound) -> Heard:
        """Feed ``block`` (16 kHz) to its recording's detector."""
        if block.rate != RATE:
            raise ValueError(f"the microphones' blocks come at {RATE} Hz, not {block.rate}")
        stream = self._streams.get(block.line)
        if stream is None:
            stream = self._streams[block.line] = _Stream(block, [], UtteranceDetector(self.cfg))
        stream.blocks.append(block.audio)
        stream.fed += block.audio.shape[-1]
        first = np.atleast_2d(block.audio)[0]
        events = stream.detector.feed(np.clip(np.round(first), -32768, 32767).astype(np.int16))
        if block.ends:
            events += stream.detector.finish()
        started = any(isinstance(e, SpeechStart) for e in events)
        stream.voiced = stream.voiced or started
        utterances = [self._hand_on(stream, e.decided) for e in events
                      if isinstance(e, Utterance)]
        whole = block.ends and not stream.made_out
        if whole:                # nothing made out yet: the recogniser judges it whole
            stream.handed = 0
            utterances = [self._hand_on(stream, stream.fed)]
        if block.ends:
            del self._streams[block.line]
        return Heard(started, utterances, whole, stream.voiced)

    def made_out(self, line: int) -> None:
        """Words were recognised in an utterance of ``line``'s recording."""
        if (stream := self._streams.get(line)) is not None:
            stream.made_out = True

    @staticmethod
    def _hand_on(stream: _Stream, upto: int) -> Sound:
        """The recording's samples from where the last utterance ended to ``upto``."""
        audio = np.concatenate(stream.blocks, axis=-1)[..., stream.handed:upto]
        stream.handed = upto
        return dataclasses.replace(stream.sound, audio=audio, ends=True)
