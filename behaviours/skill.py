"""Building blocks of the skills: a behaviour base class with access to the household and
the shared blackboard keys, and the leaves every skill reuses (say, relieve a drive)."""

from __future__ import annotations

import py_trees
from py_trees.common import Access, Status

from app.mind.personality import ACTIONS
from behaviours.context import KEYS, Household
from perception.detector.yolo import Detection


class HouseholdBehaviour(py_trees.behaviour.Behaviour):
    """A behaviour that sees the household and may read or write the blackboard keys it
    names (``reads``/``writes``; writing implies reading)."""

    def __init__(self, name: str, house: Household, reads: tuple[str, ...] = (),
                 writes: tuple[str, ...] = ()) -> None:
        super().__init__(name)
        self.house = house
        self.bb = self.attach_blackboard_client(name=name)
        for key in reads:
            assert key in KEYS, key
            self.bb.register_key(key, access=Access.READ)
        for key in writes:
            assert key in KEYS, key
            self.bb.register_key(key, access=Access.WRITE)

    @property
    def now(self) -> float:
        """Simulated time (s)."""
        return self.house.now

    def emit(self, kind: str, **fields: object) -> None:
        """Log an event tagged with this behaviour's name."""
        self.house.events.emit(kind, behaviour=self.name, **fields)


class Say(HouseholdBehaviour):
    """Speak a sentence; RUNNING for as long as saying it takes."""

    def __init__(self, name: str, house: Household, text: str) -> None:
        super().__init__(name, house)
        self.text = text
        self._until = 0.0

    def initialise(self) -> None:
        self._until = self.now + self.house.speaker.say(self.text, behaviour=self.name)

    def update(self) -> Status:
        return Status.SUCCESS if self.now >= self._until else Status.RUNNING


class Relieve(HouseholdBehaviour):
    """Satisfy the action's drive: RUNNING until the homeostasis tick has counted the
    action's duration (Table 4.2) in relieving steps. Put it in parallel with the activity
    that satisfies the drive (dancing, charging, ...)."""

    def __init__(self, name: str, house: Household, action: str) -> None:
        super().__init__(name, house, reads=("progress",), writes=("relieving",))
        self.steps = int(house.homeostasis.duration[ACTIONS.index(action)])

    def initialise(self) -> None:
        self.bb.relieving = True

    def update(self) -> Status:
        return Status.SUCCESS if self.bb.progress >= self.steps else Status.RUNNING

    def terminate(self, new_status: Status) -> None:
        self.bb.relieving = False


def people_in_view(house: Household, detections: list[Detection]) -> list[Detection]:
    """Person boxes confident enough for the skills, tallest (nearest) first."""
    keep = [d for d in detections
            if d.cls == "person" and d.conf >= house.config.perception.min_conf]
    return sorted(keep, key=lambda d: -d.height)
