"""Posture building blocks of the body skills (rest, sing_dance, stand_by): go to a named
posture and wait for it, and make sure an interrupted or failed skill leaves the robot
commanded to stand."""

from __future__ import annotations

import py_trees
from py_trees.common import Status

from behaviours.context import Context
from behaviours.skill import ContextBehaviour
from robot.body import Body

STAND = "Stand"


class GoToPosture(ContextBehaviour):
    """Command a posture of robot.yaml; SUCCESS once it is reached, FAILURE (and a
    ``posture_timeout`` event naming the joints still off target) if that takes longer than
    ``timeout_s``."""

    def __init__(self, ctx: Context, posture: str, speed: float | None, timeout_s: float,
                 name: str | None = None) -> None:
        super().__init__(name or posture, ctx)
        self.posture = posture
        self.speed = speed
        self.timeout_s = timeout_s
        self._deadline = 0.0

    def initialise(self) -> None:
        self.ctx.robot.joints.set_posture(self.posture, self.speed)
        self._deadline = self.now + self.timeout_s

    def update(self) -> Status:
        if self.ctx.robot.joints.posture_reached():
            return Status.SUCCESS
        if self.now >= self._deadline:
            self.emit("posture_timeout", posture=self.posture,
                      off_target=self.ctx.robot.joints.off_target())
            return Status.FAILURE
        return Status.RUNNING


class StandOnExit(py_trees.decorators.PassThrough):
    """Pass the child's status through; when the child is interrupted while running (stopped
    with INVALID, e.g. by the action's guard) or fails, command the Stand posture."""

    def __init__(self, name: str, child: py_trees.behaviour.Behaviour, robot: Body) -> None:
        super().__init__(name, child)
        self.robot = robot

    def terminate(self, new_status: Status) -> None:
        interrupted = new_status == Status.INVALID and self.status == Status.RUNNING
        if interrupted or new_status == Status.FAILURE:
            self.robot.joints.set_posture(STAND)
