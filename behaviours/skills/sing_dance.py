"""Sing and dance: perform a routine of ``config/dances.yaml`` (keyframed arm, head
and hip gestures with sung lines, docs/skills_body.md), looped for the action's Table 4.2
duration, then stand. A song someone asked for is danced as asked; otherwise each start of
the skill takes the next routine in the file's order."""

from __future__ import annotations

from typing import Any

import py_trees
from py_trees.common import Status

from behaviours.context import Context
from behaviours.skill import ContextBehaviour, Relieve
from behaviours.skills.posture import STAND, GoToPosture, StandOnExit
from robot.dances import Routine, load_dances


class Dance(ContextBehaviour):
    """Sing each lyric line and command each keyframe at its time, looping the routine;
    RUNNING until stopped. A start asked for by a reply (``request``) dances the routine
    of the song asked for; any other start takes the next routine (rotating). The routines
    file (``sing_dance.routines``) is loaded and checked against the robot's joint limits
    in ``setup()``."""

    def __init__(self, ctx: Context, speed: float, name: str = "Dance") -> None:
        super().__init__(name, ctx, reads=("request",))
        self.speed = speed
        self.routines: list[Routine] = []     # loaded in setup()
        self.routine: Routine | None = None   # the one danced now
        self._turn = 0
        self._pass_start = 0.0
        self._next_line = 0
        self._next_frame = 0

    def setup(self, **kwargs: Any) -> None:
        book = load_dances(self.ctx.config.sing_dance.resolved_routines(),
                           self.ctx.robot.joints.limits())
        self.routines = list(book.routines)

    def initialise(self) -> None:
        asked = self.bb.request.params.get("song") if self.bb.request is not None else None
        chosen = [r for r in self.routines if r.title == asked]
        if chosen:
            self.routine = chosen[0]
        else:
            self.routine = self.routines[self._turn % len(self.routines)]
            self._turn += 1
        self._begin_pass(self.now)
        self.emit("dance", title=self.routine.title, requested=asked)

    def _begin_pass(self, start: float) -> None:
        self._pass_start = start
        self._next_line = self._next_frame = 0

    def update(self) -> Status:
        r = self.routine
        if self.now - self._pass_start >= r.length_s - 1e-9:
            self._begin_pass(self._pass_start + r.length_s)
        due = self.now - self._pass_start + 1e-9
        while self._next_frame < len(r.keyframes) and r.keyframes[self._next_frame].at <= due:
            self.ctx.robot.joints.move(r.keyframes[self._next_frame].targets(), self.speed)
            self._next_frame += 1
        while self._next_line < len(r.lyrics) and r.lyrics[self._next_line].at <= due:
            self.ctx.speaker.say(r.lyrics[self._next_line].text, behaviour=self.name,
                                 song=r.title)
            self._next_line += 1
        return Status.RUNNING


def build(ctx: Context) -> py_trees.behaviour.Behaviour:
    """The sing/dance subtree: dance while the action's duration runs, then stand."""
    cfg = ctx.config.sing_dance
    relieve = Relieve("Dancing relieves", ctx, "sing_dance")
    perform = py_trees.composites.Parallel(
        "Perform", policy=py_trees.common.ParallelPolicy.SuccessOnSelected(children=[relieve]),
        children=[Dance(ctx, cfg.speed), relieve])
    steps = [perform, GoToPosture(ctx, STAND, None, cfg.posture_timeout_s)]
    return StandOnExit("Sing and dance", py_trees.composites.Sequence(
        "Sing and dance steps", memory=True, children=steps), ctx.robot)
