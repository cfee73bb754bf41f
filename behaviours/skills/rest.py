"""Rest: say "I need to take a rest", crouch into the rest posture, stay crouched while the
motors cool (faster there: robot.yaml's ``rest_cooling_tau_s``) for the action's Table 4.2
duration, then stand up. Interrupted or failed, the robot is commanded to stand."""

from __future__ import annotations

import py_trees

from behaviours.context import Household
from behaviours.skill import Relieve, Say
from behaviours.skills.posture import STAND, GoToPosture, StandOnExit


def build(house: Household) -> py_trees.behaviour.Behaviour:
    """The rest subtree: say, crouch, relieve while crouched, stand up."""
    cfg = house.config.rest
    steps = [
        Say("Say rest", house, cfg.say),
        GoToPosture(house, cfg.posture, cfg.speed, cfg.posture_timeout_s, name="Rest posture"),
        Relieve("Rest relieves", house, "rest"),
        GoToPosture(house, STAND, cfg.speed, cfg.posture_timeout_s, name="Stand up"),
    ]
    return StandOnExit("Rest", py_trees.composites.Sequence("Rest steps", memory=True,
                                                            children=steps), house.robot)
