"""The tree's blackboard: every key, what it holds and its value before the first tick.

All keys live at the root namespace, so that ``py_trees.display`` can show them and every
behaviour declares what it reads and writes (:class:`behaviours.skill.ContextBehaviour`).
Behaviours do not seed keys: :func:`seed` writes the initial value of every key, and the
tree builders call it (:func:`behaviours.tree.build_tree` for the run,
:func:`app.harness.skill_tree` for one skill on its own).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
import py_trees

from behaviours.context import Context
from mind.homeostasis import Homeostasis
from mind.personality import DRIVES

# Blackboard keys and what they hold.
KEYS = {
    "stimuli": "np.ndarray (3,): overheat, human_present, encouragement (0/1)",
    "drives": "np.ndarray (6,) in [0, 1]",
    "motivations": "np.ndarray (6,): eq. 3.4",
    "mood": "dict: value (eq. 3.6) and positive (bool)",
    "emotion": "float: the human's shown emotion, +1 happy, -1 sad, 0 none",
    "line_emotion": "tuple(str, float) | None: the feeling of the last line answered, read "
                    "from its words by the dialogue (happy or sad) and when; Sense takes it "
                    "as the human's emotion",
    "action": "str | None: the running action (mind.personality.ACTIONS)",
    "relieving": "bool: the running skill is satisfying its drive now",
    "progress": "int: homeostasis steps the running skill has been relieving",
    "act_status": "py_trees Status of the act subtree at the last tick",
    "frame": "np.ndarray | None: the latest head-camera frame (RGB)",
    "depth": "np.ndarray | None: its depth image (m along the optical axis, float32)",
    "frame_t": "float: when it was taken (simulated s)",
    "detections": "list[Detection] in the latest frame",
    "faces": "list[(Detection, str | None)]: each confident face box in it and the expression "
             "it shows (happy, sad; None: neutral or unread)",
    "facings": "list[Facing | None]: which way the person in each box of `detections` looks "
               "(the facing model); None for other boxes or without the model",
    "voices": "list[VoiceHeard]: the voices picked up at this tick, made out or not, with "
              "where they came from and how far they stood over the noise",
    "heard": "list[HeardLine]: what people said to the robot, not yet answered",
    "voice_started": "float: when (simulated s) speech last began at the microphones, as "
                     "their voice-activity detector heard it (a reply then stops)",
    "feedback": "list[FeedbackEvent]: praise or scolding not yet credited to an action",
    "person": "tuple[str, float] | None: who last spoke to the robot or gave it feedback, "
              "and when (simulated s)",
    "must_finish": "bool: the running action is a safety one (critical charge, rest when "
                   "overheated) that a line said to the robot must not interrupt",
    "request": "Action | None: what a reply promised to do (sing a song), started next",
    "listening_to": "float | None: world bearing (rad) of the voice being answered",
    "tracking": "float: camera rate (Hz) a skill steering by person boxes asks for; 0: none",
    "people_seen": "list[(x, y, t)]: where (m, world) and when the robot located people, "
                   "this run (find people's memory)",
    "rooms_searched": "dict[str, float]: room -> when find people last looked round there "
                      "and greeted nobody",
}


def motivations_and_mood(homeostasis: Homeostasis, drives: np.ndarray, stimuli: np.ndarray,
                         emotion: float) -> dict[str, Any]:
    """The ``motivations`` (eq. 3.4) and ``mood`` (eq. 3.6) of these drives, stimuli and
    shown emotion: the homeostasis tick publishes them every step, :func:`seed` from the
    initial drives."""
    value = float(homeostasis.mood_value(drives, stimuli[2], emotion))
    return {"motivations": homeostasis.motivations(drives, stimuli),
            "mood": {"value": value, "positive": bool(homeostasis.mood_positive(value))}}


def initial_values(homeostasis: Homeostasis, initial_drives: Mapping[str, float]
                   ) -> dict[str, Any]:
    """The value of every key of :data:`KEYS` before the first tick: the scenario's initial
    drives with their motivations and mood (no stimulus, no emotion); no action yet and
    nothing relieving; no camera frame yet (``frame_t`` -inf, so Sense takes one at the
    first tick), nothing detected, heard, promised or requested (no voice started);
    ``tracking`` 0.0: no skill asks for a camera rate."""
    drives = np.array([initial_drives[d] for d in DRIVES], dtype=np.float64)
    stimuli, emotion = np.zeros(3), 0.0
    values = {
        "stimuli": stimuli, "drives": drives,
        **motivations_and_mood(homeostasis, drives, stimuli, emotion), "emotion": emotion,
        "line_emotion": None, "action": None, "relieving": False, "progress": 0, "act_status": None,
        "frame": None, "depth": None, "frame_t": -np.inf, "detections": [], "faces": [],
        "facings": [], "voices": [], "heard": [], "voice_started": -np.inf,
        "feedback": [], "person": None, "must_finish": False, "request": None,
        "listening_to": None, "tracking": 0.0,
        "people_seen": [], "rooms_searched": {},
    }
    assert values.keys() == KEYS.keys(), sorted(values.keys() ^ KEYS.keys())
    return values


def seed(ctx: Context, initial_drives: Mapping[str, float], **values: Any) -> None:
    """Write the initial value of every key (:func:`initial_values`) onto the blackboard;
    ``values`` replace some of them (the skill harness fixes ``action``)."""
    unknown = sorted(values.keys() - KEYS.keys())
    if unknown:
        raise KeyError(f"not blackboard keys: {unknown}")
    for key, value in {**initial_values(ctx.homeostasis, initial_drives), **values}.items():
        py_trees.blackboard.Blackboard.set(f"/{key}", value)
