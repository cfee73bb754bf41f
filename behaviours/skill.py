"""Building blocks of the skills: a behaviour base class with access to the tree's
:class:`~behaviours.context.Context` and the shared blackboard keys, and the leaves every
skill reuses (say, relieve a drive).

Like every behaviour here, their ``__init__`` only stores arguments and declares blackboard
keys, so that a tree can be built (and drawn) cheaply; one-time work that needs the
simulation or a file goes in ``setup()``, which the tree calls once before the first tick
(:class:`behaviours.ticking.SimulationTree`)."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import py_trees
from py_trees.common import Access, Status

from behaviours.blackboard import KEYS
from behaviours.context import Context
from mind.personality import ACTIONS
from perception.detector.yolo import Detection
from perception.facing.model import Facing


class ContextBehaviour(py_trees.behaviour.Behaviour):
    """A behaviour that sees the context and may read or write the blackboard keys it names
    (``reads``/``writes``; writing implies reading)."""

    def __init__(self, name: str, ctx: Context, reads: tuple[str, ...] = (),
                 writes: tuple[str, ...] = ()) -> None:
        super().__init__(name)
        self.ctx = ctx
        self.bb = self.attach_blackboard_client(name=name)
        for key in reads:
            assert key in KEYS, key
            self.bb.register_key(key, access=Access.READ)
        for key in writes:
            assert key in KEYS, key
            self.bb.register_key(key, access=Access.WRITE)

    @property
    def now(self) -> float:
        """Simulated time (s)."""
        return self.ctx.now

    def emit(self, kind: str, **fields: object) -> None:
        """Log an event tagged with this behaviour's name."""
        self.ctx.events.emit(kind, behaviour=self.name, **fields)

    def tick(self) -> Iterator[py_trees.behaviour.Behaviour]:
        """py_trees' tick, its faults contained (:func:`contained_tick`)."""
        yield from contained_tick(self, self.ctx, super().tick())


def contained_tick(node: py_trees.behaviour.Behaviour, ctx: Context,
                   ticks: Iterator[py_trees.behaviour.Behaviour],
                   ) -> Iterator[py_trees.behaviour.Behaviour]:
    """``node``'s py_trees tick (``ticks``). When the context contains faults (household
    runs), an exception inside it fails ``node`` with a ``fault`` event instead of ending
    the run; tests leave it off, so a bug still raises there."""
    if not ctx.contain_faults:
        yield from ticks
        return
    try:
        yield from ticks
    except Exception as exc:
        ctx.events.emit("fault", behaviour=node.name, fault="behaviour_error",
                        error=f"{type(exc).__name__}: {exc}"[:300],
                        recovery="this behaviour fails; the tree goes on")
        try:
            node.stop(Status.FAILURE)
        except Exception:   # its own clean-up failed too: the status still says FAILURE
            node.status = Status.FAILURE
        yield node


class Say(ContextBehaviour):
    """Speak a sentence; RUNNING for as long as saying it takes."""

    def __init__(self, name: str, ctx: Context, text: str) -> None:
        super().__init__(name, ctx)
        self.text = text
        self._until = 0.0

    def initialise(self) -> None:
        self._until = self.now + self.ctx.speaker.say(self.text, behaviour=self.name)

    def update(self) -> Status:
        return Status.SUCCESS if self.now >= self._until else Status.RUNNING


class Relieve(ContextBehaviour):
    """Satisfy the action's drive: RUNNING until the homeostasis tick has counted the
    action's duration (Table 4.2) in relieving steps. Put it in parallel with the activity
    that satisfies the drive (dancing, charging, ...). A new action starts with the flag
    off (Decide), so a pre-empted skill's leaf leaves it alone."""

    def __init__(self, name: str, ctx: Context, action: str) -> None:
        super().__init__(name, ctx, reads=("progress", "action"), writes=("relieving",))
        self.action = action
        self.steps: int | None = None    # the action's Table 4.2 duration, set in setup()

    def setup(self, **kwargs: Any) -> None:
        self.steps = int(self.ctx.homeostasis.duration[ACTIONS.index(self.action)])

    def initialise(self) -> None:
        self.bb.relieving = True

    def update(self) -> Status:
        return Status.SUCCESS if self.bb.progress >= self.steps else Status.RUNNING

    def terminate(self, new_status: Status) -> None:
        # stopped because another action pre-empted this one, the flag is the new action's
        if self.bb.action == self.action:
            self.bb.relieving = False


def facing_of(detections: list[Detection], facings: list[Facing | None],
              box: Detection) -> Facing | None:
    """The facing Sense read for ``box``, one of ``detections`` (None: none read)."""
    return next((f for d, f in zip(detections, facings, strict=True) if d is box), None)


def people_in_view(ctx: Context, detections: list[Detection]) -> list[Detection]:
    """Person boxes confident enough for the skills, tallest (nearest) first."""
    keep = [d for d in detections
            if d.cls == "person" and d.conf >= ctx.config.perception.min_conf]
    return sorted(keep, key=lambda d: -d.height)
