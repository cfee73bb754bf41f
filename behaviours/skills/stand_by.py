"""Stand-by: stand and slowly look around (a HeadYaw sinusoid) for the Table 4.2 stand-by
duration, then recentre the head. Stand-by has no drive, but its duration is counted in
relieving steps all the same, so the Relieve leaf says when it is over."""

from __future__ import annotations

import math

import py_trees
from py_trees.common import Status

from behaviours.context import Context
from behaviours.skill import ContextBehaviour, Relieve
from behaviours.skills.posture import STAND, GoToPosture, StandOnExit

SWAY_SPEED = 1.0  # the target moves smoothly, so the ramp may follow it at full speed


class HeadSway(ContextBehaviour):
    """Turn the head as ``amplitude * sin(2 pi t / period)`` (rad) from when it starts;
    RUNNING until stopped."""

    def __init__(self, ctx: Context, amplitude: float, period_s: float,
                 name: str = "Look around") -> None:
        super().__init__(name, ctx)
        self.amplitude = amplitude
        self.period_s = period_s
        self._start = 0.0

    def initialise(self) -> None:
        self._start = self.now

    def update(self) -> Status:
        phase = 2.0 * math.pi * (self.now - self._start) / self.period_s
        self.ctx.robot.head.look(yaw=self.amplitude * math.sin(phase), speed=SWAY_SPEED)
        return Status.RUNNING


def build(ctx: Context) -> py_trees.behaviour.Behaviour:
    """The stand-by subtree: stand, look around while the duration runs, recentre."""
    cfg = ctx.config.stand_by
    relieve = Relieve("Stand-by counts", ctx, "stand_by")
    idle = py_trees.composites.Parallel(
        "Idle", policy=py_trees.common.ParallelPolicy.SuccessOnSelected(children=[relieve]),
        children=[HeadSway(ctx, cfg.head_yaw_amplitude, cfg.period_s), relieve])
    steps = [GoToPosture(ctx, STAND, None, cfg.posture_timeout_s),
             idle,
             GoToPosture(ctx, STAND, None, cfg.posture_timeout_s, name="Recentre")]
    return StandOnExit("Stand by", py_trees.composites.Sequence("Stand-by steps", memory=True,
                                                                children=steps), ctx.robot)
