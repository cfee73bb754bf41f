"""The simulated robot's microphones and tablet parts (robot/body.py): queues that the
household fills and Sense empties.

The household's sound (sim/household_sound.py) leaves each recording in
:class:`SimMicrophones` as its speaker finishes the line; the tablet's web app (during a
run, app/tablet/run_link.py) leaves typed lines and pressed thumbs in :class:`SimTablet`.
Sense takes both once per tick. A real robot's drivers would fill the same interfaces.
"""

from __future__ import annotations

from robot.percepts import FeedbackEvent, HeardLine, Sound


class SimMicrophones:
    """The recordings of lines the household's people finished saying, not yet taken."""

    def __init__(self) -> None:
        self._recorded: list[Sound] = []

    def record(self, sound: Sound) -> None:
        """Keep ``sound`` for the next :meth:`recordings`."""
        self._recorded.append(sound)

    def recordings(self) -> list[Sound]:
        """The recordings finished since the last call, oldest first."""
        taken, self._recorded = self._recorded, []
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
