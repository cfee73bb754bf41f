"""The companion's behaviour tree.

::

    Companion (sequence, re-evaluated every tick)
    ├── Sense         stimuli, heard lines, feedback and camera detections onto the blackboard
    ├── Credit        feedback to the action it follows; the household memory learns
    ├── Homeostasis   drives, motivations and mood, once per homeostasis step
    ├── Decide        safety first (low energy pre-empts), then answering whoever spoke,
    │                 then the DQN's pick when the last action ended
    ├── Promise       during a safety action: answer by voice, promise a song for after
    └── Act           status mirrored to the blackboard's ``act_status``
        └── Actions (selector)
            ├── charge?  guard: action == "charge"  -> the charge skill subtree
            ├── ...      one guarded subtree per action of mind.personality.ACTIONS
            └── stand_by?

The guards are py_trees ``EternalGuard`` decorators: when Decide switches the action the
running skill's guard fails and the skill is stopped (its ``terminate`` cleans up).

Building the tree is cheap and loads nothing (it can be drawn from a bare context);
``setup()`` (:meth:`behaviours.ticking.SimulationTree.setup`) does the one-time work.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable

import py_trees

from behaviours.blackboard import seed
from behaviours.context import Context
from behaviours.decide import Decide, Policy
from behaviours.feedback import Credit
from behaviours.homeostasis_tick import HomeostasisTick
from behaviours.listening import Promise
from behaviours.sense import Sense
from mind.personality import ACTIONS

SkillBuilder = Callable[[Context], py_trees.behaviour.Behaviour]


def skill_builders() -> dict[str, SkillBuilder]:
    """``build`` of each action's skill module ``behaviours/skills/<action>.py``."""
    return {a: importlib.import_module(f"behaviours.skills.{a}").build for a in ACTIONS}


def _guard(action: str, subtree: py_trees.behaviour.Behaviour) -> py_trees.behaviour.Behaviour:
    return py_trees.decorators.EternalGuard(
        name=f"{action}?", child=subtree, blackboard_keys=["action"],
        condition=lambda blackboard: blackboard.action == action)


def build_tree(ctx: Context, policy: Policy, initial_drives: dict[str, float],
               builders: dict[str, SkillBuilder] | None = None
               ) -> py_trees.composites.Sequence:
    """The full tree for one run (call after :func:`app.wiring.make_context`); the
    blackboard is seeded (:func:`behaviours.blackboard.seed`) with ``initial_drives``."""
    seed(ctx, initial_drives)
    builders = builders or skill_builders()
    actions = py_trees.composites.Selector(
        "Actions", memory=False, children=[_guard(a, builders[a](ctx)) for a in ACTIONS])
    act = py_trees.decorators.StatusToBlackboard("Act", child=actions,
                                                 variable_name="act_status")
    return py_trees.composites.Sequence(
        "Companion", memory=False,
        children=[Sense(ctx), Credit(ctx), HomeostasisTick(ctx), Decide(ctx, policy),
                  Promise(ctx), act])


def render(root: py_trees.behaviour.Behaviour, show_status: bool = False) -> str:
    """The tree as unicode text (the shape snapshot; with statuses when ``show_status``)."""
    return py_trees.display.unicode_tree(root, show_status=show_status)
