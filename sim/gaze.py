"""Whom people look at while they talk.

Someone talking to another person turns to them; talking to the robot, they turn to the
robot. People in a household run do the same: a speaker who is not walking turns to face
whom their line is for when they start it, keeps facing them while they speak and for
``LOOK_AFTER_S`` after, then turns back the way they faced before (unless they have moved
meanwhile). A line for everyone, or for someone not in the house, turns no one. This is
what lets the robot tell from its camera, not from the script, that a line was not said to
it (docs/speech.md, *Who a line is for*).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from robot.percepts import AUDIENCES, SayEvent
from sim.world import World

LOOK_AFTER_S = 4.0   # s a speaker keeps facing whom they spoke to once the line ends


@dataclass
class _Turn:
    until: float       # when they turn back
    yaw: float         # the way they faced before
    turned: float      # the way they faced while talking


class TalkGaze:
    """Turns the people of ``world`` to whom they talk to, and back."""

    def __init__(self, world: World) -> None:
        self.world = world
        self._turns: dict[str, _Turn] = {}

    def turn(self, event: SayEvent, until: float, robot: tuple[float, float]) -> None:
        """``event``'s speaker faces the one it is said to (the robot at ``robot``) until
        ``until`` plus ``LOOK_AFTER_S``, when they are in the house and not walking."""
        people, name = self.world.people, event.person
        if event.to == AUDIENCES[0]:      # the robot
            target: tuple[float, float] | None = robot
        else:
            other = people.get(event.to)
            target = None if other is None else (other.x, other.y)
        if target is None or not self.world.standing_still(name):
            return
        person = people[name]
        yaw = math.atan2(target[1] - person.y, target[0] - person.x)
        before = self._turns[name].yaw if name in self._turns else person.yaw
        person.place(person.x, person.y, yaw)
        self._turns[name] = _Turn(until + LOOK_AFTER_S, before, yaw)

    def release(self, t: float) -> None:
        """Everyone whose look is over at ``t`` turns back, if they stayed where they were."""
        for name, turn in list(self._turns.items()):
            if turn.until > t:
                continue
            del self._turns[name]
            person = self.world.people.get(name)
            if person is not None and self.world.standing_still(name) \
                    and person.yaw == turn.turned:
                person.place(person.x, person.y, turn.yaw)
