"""Rest: say "I need to take a rest", crouch into the rest posture, stay crouched while the
motors cool (faster there: robot.yaml's ``rest_cooling_tau_s``) for the action's Table 4.2
duration, then stand up. Interrupted or failed, the robot is commanded to stand."""

from __future__ import annotations

import py_trees

from behaviours.context import Context
from behaviours.skill import Relieve, Say
from behaviours.skills.posture import STAND, GoToPosture, StandOnExit


def build(ctx: Context) -> py_trees.behaviour.Behaviour:
    """The rest subtree: say, crouch, relieve while crouched, stand up."""
    cfg = ctx.config.rest
    steps = [
        Say("Say rest", ctx, cfg.say),
        GoToPosture(ctx, cfg.posture, cfg.speed, cfg.posture_timeout_s, name="Rest posture"),
        Relieve("Rest relieves", ctx, "rest"),
        GoToPosture(ctx, STAND, cfg.speed, cfg.posture_timeout_s, name="Stand up"),
    ]
    return StandOnExit("Rest", py_trees.composites.Sequence("Rest steps", memory=True,
                                                            children=steps), ctx.robot)
