"""Tree snapshots: the behaviour tree's shape, and its statuses at chosen ticks of a seeded
scenario (the low-battery night: critical energy pre-empts at once and the robot goes to
charge), compared with the files in tests/snapshots/. Refresh them after an intended change
with ``make snapshots``.

Neither test loads a model. The shape is drawn from a tree that is only built (no
``setup()``). The statuses come from the tree set up and ticked without a detector
(detections stay empty), question generator or dialogue model; a stub policy and a stub
dialogue fail the test if the tree ever consults them: the charge that critical energy
forces runs through all 400 ticks, so the policy is never asked."""

from __future__ import annotations

import difflib
import os
from pathlib import Path

import numpy as np
import py_trees
import pytest

from app.wiring import make_context
from behaviours.ticking import SimulationTree
from behaviours.tree import build_tree, render
from sim.scenario import load_scenario
from sim.simulation import Simulation

SNAPSHOTS = Path(__file__).parent / "snapshots"
UPDATE = os.environ.get("UPDATE_SNAPSHOTS") == "1"
SCENARIO = Path(__file__).resolve().parents[1] / "worlds" / "low_battery_night.yaml"
TICKS = (1, 30, 150, 400)


def check(name: str, text: str) -> None:
    """Compare ``text`` with the stored snapshot (or store it when refreshing)."""
    path = SNAPSHOTS / name
    if UPDATE:
        path.write_text(text)
        return
    assert path.is_file(), f"{path} is missing: run `make snapshots`"
    stored = path.read_text()
    diff = "".join(difflib.unified_diff(stored.splitlines(True), text.splitlines(True),
                                        "stored", "now"))
    assert text == stored, f"{name} differs from its snapshot (`make snapshots` refreshes):\n{diff}"


class NoPolicy:
    """A policy the snapshot run must never need."""

    def act(self, motivations: np.ndarray) -> str:
        pytest.fail(f"the policy was consulted (motivations {motivations})")


class NoDialogue:
    """A dialogue manager the snapshot run must never need (the chat skill's setup wants
    one)."""

    def respond(self, text: str, mood: str) -> None:
        pytest.fail(f"the dialogue manager was asked to answer {text!r}")


def test_tree_shape():
    with Simulation(load_scenario(SCENARIO)) as sim:
        root = build_tree(make_context(sim), NoPolicy(), sim.scenario.robot.initial_drives())
        check("tree.txt", render(root) + "\n")


def test_statuses_at_chosen_ticks():
    with Simulation(load_scenario(SCENARIO)) as sim:
        ctx = make_context(sim, dialogue=NoDialogue())
        tree = SimulationTree(build_tree(ctx, NoPolicy(), sim.scenario.robot.initial_drives()),
                              sim, ctx)
        tree.setup()
        bb = py_trees.blackboard.Client(name="snapshot")
        bb.register_key("action", access=py_trees.common.Access.READ)
        parts = []
        for tick in range(1, max(TICKS) + 1):
            tree.tick()
            if tick in TICKS:
                parts.append(f"tick {tick} (t = {sim.t:.1f} s, action = {bb.action})\n"
                             + render(tree.root, show_status=True))
        tree.stop()
    check("statuses.txt", "\n".join(parts) + "\n")
