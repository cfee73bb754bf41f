"""Listening: the lines people said to the robot, and the two reactions to them that run
outside any one skill.

- :func:`pending`: the queued lines still worth answering (a line older than
  ``chat.max_heard_age_s`` is dropped, unless the robot promised to answer it);
- :class:`Promise`: while a safety action must finish (charging on critical energy, resting
  when overheated), the robot tells each new speaker that it will come back to them and
  marks their line promised; Decide starts the chat once the safety action is over;
- :class:`FaceSpeaker`: turns the head, then the base, to the voice being answered.
"""

from __future__ import annotations

import dataclasses
import math

from py_trees.common import Status

from app.sim.hearing import HeardLine
from app.sim.robot import wrap_angle
from behaviours.context import Context
from behaviours.skill import ContextBehaviour


def pending(lines: list[HeardLine], now: float, max_age_s: float) -> list[HeardLine]:
    """The lines to answer, oldest first: the promised ones and those at most ``max_age_s``
    old."""
    return [line for line in lines if line.promised or now - line.t <= max_age_s]


def head_error(ctx: Context, bearing: float) -> float:
    """How far (rad) the head points from ``bearing`` (world frame), given the base's yaw
    and the HeadYaw joint."""
    yaw = ctx.robot.pose()[2] + ctx.robot.joint_positions()["HeadYaw"]
    return wrap_angle(bearing - yaw)


class Promise(ContextBehaviour):
    """Always SUCCESS. While ``must_finish``, say the promise to each new line's speaker and
    mark the line promised."""

    def __init__(self, ctx: Context, name: str = "Promise") -> None:
        super().__init__(name, ctx, reads=("must_finish", "action"), writes=("heard",))

    def update(self) -> Status:
        if not self.bb.must_finish:
            return Status.SUCCESS
        fresh = [line for line in self.bb.heard if not line.promised]
        if fresh:
            cfg = self.ctx.config.listening
            text = cfg.promise.format(activity=cfg.activities.get(self.bb.action, "finish this"))
            self.ctx.speaker.say(text, behaviour=self.name, to=fresh[0].person,
                                 lines=[line.line for line in fresh])
            self.bb.heard = [dataclasses.replace(line, promised=True) if not line.promised
                             else line for line in self.bb.heard]
        return Status.SUCCESS


class FaceSpeaker(ContextBehaviour):
    """Turn to ``listening_to``: the head at once (within its joint range), the base after
    it so that the head comes back to centre. RUNNING until stopped; the base stops when it
    faces the voice, or when there is no voice to face."""

    def __init__(self, ctx: Context, name: str = "Face the speaker") -> None:
        super().__init__(name, ctx, reads=("listening_to",))

    def update(self) -> Status:
        robot, cfg = self.ctx.robot, self.ctx.config.listening
        bearing = self.bb.listening_to
        if bearing is None:
            robot.set_base_velocity(0.0, 0.0, 0.0)
            return Status.RUNNING
        off_base = wrap_angle(bearing - robot.pose()[2])
        lo, hi = robot.joint_limits()["HeadYaw"]
        robot.move_joints({"HeadYaw": min(max(off_base, lo), hi)}, cfg.head_speed)
        facing = abs(off_base) <= math.radians(cfg.facing_tolerance_deg)
        turn = 0.0 if facing else math.copysign(min(cfg.turn_speed, cfg.turn_gain
                                                    * abs(off_base)), off_base)
        robot.set_base_velocity(0.0, 0.0, turn)
        return Status.RUNNING

    def terminate(self, new_status: Status) -> None:
        self.ctx.robot.set_base_velocity(0.0, 0.0, 0.0)
