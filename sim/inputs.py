"""The simulated robot's microphones and tablet parts (robot/body.py): queues that the
household fills and Sense empties.

The household's sound (sim/household_sound.py) hands each line's recording to
:class:`SimMicrophones` as its speaker starts it, and the microphones give it out in blocks
as the simulated time reaches them; the tablet's web app (during a run,
app/tablet/run_link.py) leaves typed lines and pressed thumbs in :class:`SimTablet`. Sense
takes both once per tick. A real robot's drivers would fill the same interfaces.
"""

from __future__ import annotations

import dataclasses

from robot.percepts import FeedbackEvent, HeardLine, Sound


@dataclasses.dataclass
class _Recording:
    sound: Sound
    begins: float       # the time (s) of its first sample
    given: int = 0      # samples given out so far


class SimMicrophones:
    """The recordings of lines being said, given out block by block as time passes."""

    def __init__(self) -> None:
        self._recording: list[_Recording] = []
        self._blocks: list[Sound] = []

    def record(self, sound: Sound, begins: float | None = None) -> None:
        """Give out ``sound`` from ``begins`` on (s; its first sample is then), as
        :meth:`advance` reaches it; at once, whole, without ``begins`` (the fast hearing
        path)."""
        if begins is None:
            self._blocks.append(sound)
        else:
            self._recording.append(_Recording(sound, begins))

    def advance(self, t: float) -> None:
        """Cut the blocks of every recording up to time ``t`` (s)."""
        for r in self._recording:
            total = r.sound.audio.shape[-1]
            upto = min(total, max(r.given, round((t - r.begins) * r.sound.rate)))
            if upto > r.given:
                block = r.sound.audio[..., r.given:upto]
                self._blocks.append(dataclasses.replace(r.sound, audio=block,
                                                        ends=upto == total))
                r.given = upto
        self._recording = [r for r in self._recording if r.given < r.sound.audio.shape[-1]]

    def recordings(self) -> list[Sound]:
        """The blocks recorded since the last call, oldest first."""
        taken, self._blocks = self._blocks, []
        return taken


class SimTablet:
    """What people typed or pressed on the chest tablet, not yet taken."""

    def __init__(self) -> None:
        self._touched: list[HeardLine | FeedbackEvent] = []

    def touch(self, entry: HeardLine | FeedbackEvent) -> None:
        """A line typed (as heard, with its words as given) or a thumb pressed."""
        self._touched.append(entry)

    def inputs(self) -> list[HeardLine | FeedbackEvent]:
        """What was typed or pressed since the last call, oldest first."""
        taken, self._touched = self._touched, []
        return taken
