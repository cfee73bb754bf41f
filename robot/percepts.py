"""What reaches the robot's senses from people: the recordings its microphones make of a
line (:class:`Sound`), the voices it picked up in them (:class:`VoiceHeard`) and the lines
it recognised (:class:`HeardLine`), and the social events a household hands it directly
(docs/what_the_robot_is_given.md)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

AUDIENCES = ("robot", "everyone")  # besides a person's name, who a line can be said to


@dataclass(frozen=True)
class Sound:
    """A recording of one line: ``line`` numbers it within the run, ``audio`` holds the
    samples at ``rate`` Hz (one microphone's, or ``(4, n)``: each of the head's);
    ``heading`` (rad, world frame) is where the robot's head faced as it recorded them (its
    own pose and joints). ``bearing`` (rad, world frame) is where the voice came from as a
    localiser the simulation stands in for placed it, given only with one microphone's
    recording, which cannot place it; from the head's four the robot finds it itself.
    Whether the words are encouragement is for the robot to make out from them.

    The microphones hand a line's recording on in blocks as it is said (``audio`` the block's
    samples; ``ends``: the recording's last block), so that the robot itself decides where
    the speech starts and ends (behaviours/voice_streams.py).

    On a simulator's fast hearing path (``sim/household_sound.py``, docs/speech.md) no audio
    is made: ``audio`` is empty, ``words`` holds what was said and ``snr_db`` how far it
    stood over the noise, standing in for a recogniser that makes out every audible line;
    it comes whole once the line is said."""

    line: int
    t: float
    person: str
    bearing: float | None
    audio: np.ndarray
    rate: int
    heading: float
    words: str | None = None
    snr_db: float | None = None
    ends: bool = True


@dataclass(frozen=True)
class VoiceHeard:
    """A voice the microphones picked up as line ``line`` of ``person``: where it came
    from (``bearing``, rad, world frame), how far it stood over the noise (``snr_db``) and
    whether the recogniser made out any words (``made_out``)."""

    line: int
    t: float
    person: str
    bearing: float
    snr_db: float
    made_out: bool


@dataclass(frozen=True)
class HeardLine:
    """A line the robot recognised in a :class:`Sound`: ``text`` is its transcript,
    ``confidence`` how sure the recogniser was; ``promised``: the robot told the speaker it
    would answer later; ``unclear``: too unsure to act on, so the robot asks again;
    ``snr_db``: the speech's loudness over the noise, as the recogniser estimated it;
    ``by_name``: the words said whom the line is for (a name, a title, "robot",
    "everyone"; typed lines are the robot's), else it was taken as the robot's for want of
    a name; ``ended``: when the robot had heard it out."""

    line: int
    t: float
    person: str
    text: str
    to: str
    bearing: float
    confidence: float = 1.0
    promised: bool = False
    unclear: bool = False
    snr_db: float = float("inf")   # how far the speech stood over the noise (typed: no noise)
    by_name: bool = True
    ended: float = 0.0             # when the robot had heard it out (s)

    @property
    def made_out(self) -> bool:
        """Whether any words were made out (a voice of which none were is still queued,
        for the robot to respond to)."""
        return bool(self.text)

    @property
    def to_robot(self) -> bool:
        """Whether the line was meant for the robot (or for everyone)."""
        return self.to in AUDIENCES


@dataclass(frozen=True)
class SayEvent:
    """A person says ``text`` to ``to``: ``robot``, ``everyone`` or another person's name."""

    t: float
    person: str
    text: str
    to: str = "robot"


@dataclass(frozen=True)
class EncourageEvent:
    """A person encourages the robot (the thesis' encouragement stimulus) with ``text``."""

    t: float
    person: str
    text: str


@dataclass(frozen=True)
class EmotionEvent:
    """A person shows an emotion: ``happy``, ``sad`` or ``neutral``."""

    t: float
    person: str
    emotion: str


@dataclass(frozen=True)
class FeedbackEvent:
    """A person praises (``value`` +1) or scolds (-1) the robot, optionally naming the
    action it is ``about``."""

    t: float
    person: str
    value: int
    about: str | None


SocialEvent = SayEvent | EncourageEvent | EmotionEvent | FeedbackEvent
