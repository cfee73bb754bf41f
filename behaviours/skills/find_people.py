"""Find people: look for a person with the YOLO detector, turn to them and walk
up to them with two simple-pid loops, greet them once their face confirms they look at the
robot, and keep them centred while the action's Table 4.2 duration runs. Asked to go to a
voice the robot could not make out (``request``, from the chat skill), it turns towards
the voice first, follows the person seen there, and asks them to say it again instead of
greeting.

Only the detector's boxes on the blackboard steer the robot (no simulator ground truth):

- heading: the person box's horizontal offset from the image centre, normalised to
  [-1, 1], drives the turn rate towards 0;
- approach: the person's distance, read from the head camera's depth image inside their
  box, drives the forward speed until it reaches ``target_distance_m`` (their body centre
  then stands about 1.0 m away, whether they stand or sit; docs/find_people.md).

The controllers act once per fresh camera frame; in between the base holds its command for
up to 1.5 frame periods, then stops. The approach is a subtree whose leaves are its phases
(search, approach, wait for the face, detour or circle, give up; ``approach_phases.py``), so
the tree's snapshot and the live view show which one runs; docs/find_people.md describes
them and their settings, grouped by phase in ``config/behaviour.yaml``. The shared steering
pieces live in ``box_steering.py``.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import py_trees
from py_trees.common import Access, ParallelPolicy, Status
from py_trees.composites import Selector, Sequence

from behaviours.context import Context
from behaviours.skill import ContextBehaviour, Relieve, contained_tick
from behaviours.skills import approach_phases as phases
from behaviours.skills.approach import Approach
from behaviours.skills.box_steering import STEERING_READS, STEERING_WRITES, Steering, Tracking
from dialogue.qa.base import Action


class ApproachPerson(Sequence):
    """Search, centre and approach a person until they are ``target_distance_m`` away, as a
    subtree of phases (``approach_phases.py``): SUCCESS there once their face has been seen
    in ``face.frames`` frames since the robot began to follow them (their front is turned
    to it); FAILURE after ``timeout_s``. Every camera frame, the first phase that applies
    acts: a detour under way; the search while nobody is confirmed in view; dropping a box
    that is no person; then, closing in, going round to their front, greeting, giving up,
    circling, waiting for the face, a detour round furniture, or walking up. The phases
    share one :class:`~behaviours.skills.approach.Approach`, which this node sets up,
    resets when it starts and leaves with the base stopped."""

    def __init__(self, ctx: Context, name: str = "Approach a person") -> None:
        super().__init__(name, memory=False)
        self.ctx = ctx
        self.bb = bb = self.attach_blackboard_client(name=name)
        for key in (*STEERING_READS, "facings", "request"):
            bb.register_key(key, access=Access.READ)
        for key in (*STEERING_WRITES, "people_seen", "rooms_searched"):
            bb.register_key(key, access=Access.WRITE)
        self.approach = a = Approach(ctx, bb, name)
        closing_in = Selector("Close in", memory=False, children=[
            phases.ToFront("Go round to their front", a), phases.Found("Found: face seen", a),
            phases.GiveUp("Give up", a), phases.Orbit("Circle them", a),
            phases.WaitForFace("Wait for the face", a),
            phases.FurnitureDetour("Detour round furniture", a), phases.WalkUp("Walk up", a)])
        what = Selector("What to do", memory=False, children=[
            phases.Searching("Search", a), phases.NotAPerson("Not a person", a),
            Sequence("Approach", memory=False,
                     children=[phases.Measure("Measure", a), closing_in])])
        phase = Selector("Phase", memory=False, children=[
            phases.OnDetour("On a detour", a),
            Sequence("Person in view", memory=False,
                     children=[phases.FollowBox("Follow the box", a), what])])
        self.add_children([phases.WithinTime("Within time", a),
                           phases.FreshFrame("Fresh frame", a), phase])

    def setup(self, **kwargs: Any) -> None:
        self.approach.setup()

    def initialise(self) -> None:
        self.approach.reset()
        if (voice := voice_to_go_to(self.bb.request)) is not None:
            self.approach.towards(voice["bearing"])

    def terminate(self, new_status: Status) -> None:
        self.ctx.robot.base.stop()

    def tick(self) -> Iterator[py_trees.behaviour.Behaviour]:
        """py_trees' tick, a fault in any phase failing the whole approach (as for a leaf:
        :func:`~behaviours.skill.contained_tick`)."""
        yield from contained_tick(self, self.ctx, super().tick())


def voice_to_go_to(request: Action | None) -> dict[str, Any] | None:
    """The voice find people was asked to go to (its ``bearing``, rad, world frame, and
    ``line``: a voice the robot could not make out), or None."""
    if request is None or request.name != "find_people":
        return None
    return request.params


class Greet(ContextBehaviour):
    """Greet the person found; asked to go to a voice it could not make out, ask them to
    say it again instead (and they hear the request). RUNNING while saying it."""

    def __init__(self, ctx: Context, name: str = "Greet") -> None:
        super().__init__(name, ctx, reads=("request",))
        self._until = 0.0

    def initialise(self) -> None:
        ctx, voice = self.ctx, voice_to_go_to(self.bb.request)
        if voice is None:
            text = ctx.config.find_people.greet
        else:
            text = ctx.config.listening.unmade.say_again
            ctx.ask_again(voice["line"], False)
        self._until = self.now + ctx.speaker.say(
            text, behaviour=self.name, **({} if voice is None else {"line": voice["line"],
                                                                    "route": "say_again"}))

    def update(self) -> Status:
        return Status.SUCCESS if self.now >= self._until else Status.RUNNING


class KeepCentred(ContextBehaviour):
    """Turn so that the followed person stays centred (heading PID only); stand still when
    nobody is seen. RUNNING until stopped. Frames come less often than while approaching,
    so each turn command lasts one approach frame period only: the heading PID then corrects
    the same share of the error per frame as it does there, instead of overshooting."""

    def __init__(self, ctx: Context, name: str = "Keep them centred") -> None:
        super().__init__(name, ctx, reads=STEERING_READS, writes=STEERING_WRITES)
        perception = ctx.config.perception
        self.steer = Steering(ctx, self.bb, perception.centring_rate,
                              hold_s=1.0 / perception.tracking_rate)

    def setup(self, **kwargs: Any) -> None:
        self.steer.setup()

    def initialise(self) -> None:
        self.steer.reset()

    def update(self) -> Status:
        steer = self.steer
        fresh = steer.fresh_detections()
        if fresh is not None:
            detections, dt = fresh
            person = steer.follow(detections)
            steer.command(0.0, 0.0, steer.heading(steer.offset(person), dt=dt) if person else 0.0)
        return Status.RUNNING

    def terminate(self, new_status: Status) -> None:
        self.ctx.robot.base.stop()


def build(ctx: Context) -> py_trees.behaviour.Behaviour:
    """The find-people subtree: approach a person, then greet them and relieve the
    belonging drive while keeping them centred."""
    greet_then_relieve = py_trees.composites.Sequence(
        "Greet and stay", memory=True,
        children=[Greet(ctx),
                  Relieve("Belonging relieves", ctx, "find_people")])
    together = py_trees.composites.Parallel(
        "With the person", policy=ParallelPolicy.SuccessOnOne(),
        children=[greet_then_relieve, KeepCentred(ctx)])
    steps = py_trees.composites.Sequence("Find people steps", memory=True,
                                         children=[ApproachPerson(ctx), together])
    return Tracking("Find people", steps, ctx)
