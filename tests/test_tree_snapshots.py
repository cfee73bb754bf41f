"""Tree snapshots: the behaviour tree's shape, and its statuses at chosen ticks of a seeded
scenario (the low-battery night: the robot goes to charge at once), compared with the files
in tests/snapshots/. Refresh them after an intended change with ``make snapshots``."""

from __future__ import annotations

import difflib
import os
from pathlib import Path

import py_trees
import pytest

from app.run import build_run
from app.sim.scenario import load_scenario
from behaviours.tree import render

SNAPSHOTS = Path(__file__).parent / "snapshots"
UPDATE = os.environ.get("UPDATE_SNAPSHOTS") == "1"
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


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    scenario = load_scenario(Path("worlds/low_battery_night.yaml"))
    r = build_run(scenario.model_copy(update={"duration": 60.0}),
                  tmp_path_factory.mktemp("run"))
    yield r
    r.sim.close()


def test_tree_shape(run):
    check("tree.txt", render(run.root) + "\n")


def test_statuses_at_chosen_ticks(run):
    bb = py_trees.blackboard.Client(name="snapshot")
    bb.register_key("action", access=py_trees.common.Access.READ)
    parts = []
    for tick in range(1, max(TICKS) + 1):
        run.tick()
        if tick in TICKS:
            parts.append(f"tick {tick} (t = {run.sim.t:.1f} s, action = {bb.action})\n"
                         + render(run.root, show_status=True))
    check("statuses.txt", "\n".join(parts) + "\n")
