"""What the phases of find people's approach share (docs/find_people.md).

The approach is a small tree (``behaviours/skills/approach_phases.py``) whose leaves take
turns each camera frame: search, approach, wait for the face, detour or circle, give up.
They share one :class:`Approach`: the box steering, the detour planner and the search
bookkeeping, what this frame showed and what the approach has learnt of the followed person
so far. The tree node that owns it (:class:`~behaviours.skills.find_people.ApproachPerson`)
sets it up, resets it on every new approach and stops the base when it ends.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import py_trees
from py_trees.common import Status
from simple_pid import PID

from behaviours.context import Context
from behaviours.skills.box_steering import Steering, has_face, make_pid
from behaviours.skills.detour import Detour
from behaviours.skills.person_front import PersonFront
from behaviours.skills.search import Search
from behaviours.skills.setbacks import Escape, Ignored
from perception.detector.yolo import Detection
from robot.geometry import wrap_angle

CUT_PX = 2   # a person box reaching this close to the frame's bottom is cut off there


@dataclass
class Closing:
    """What one frame of a confirmed person box says about closing in on them: the
    controllers' commands (forward ``vx``, turn ``wz``), where the robot stands to them, how
    long it has waited for their face, and which way they face once the facing model has
    read them (world direction, and how far from looking at the robot; rad)."""

    vx: float = 0.0
    wz: float = 0.0
    close: bool = False      # at most about the target distance away
    arrived: bool = False    # about at it, and the box centred
    waited: float = 0.0      # s since the face wait began
    reading: tuple[float, float] | None = None


class Approach:
    """The shared state of one approach: the parts set up once (:meth:`setup`), this
    frame's view, and what the approach knows of the followed person (:meth:`reset`)."""

    def __init__(self, ctx: Context, bb: py_trees.blackboard.Client, name: str) -> None:
        self.ctx, self.bb, self.name = ctx, bb, name
        self.cfg = ctx.config.find_people
        self.steer = Steering(ctx, bb, ctx.config.perception.tracking_rate)
        self.pid: PID | None = None              # set in setup(), with the detour planner
        self.detour: Detour | None = None
        self.search: Search | None = None
        self.front: PersonFront | None = None    # which way they face
        self.escape = Escape(self.cfg)           # backing up and stepping aside
        self.ignored = Ignored(self.cfg)         # floor spots given up on -> until (s)
        # this frame
        self.detections: list[Detection] = []
        self.dt = 0.0                            # s since the previous frame
        self.person: Detection | None = None     # the followed box
        self.closing = Closing()
        # the approach so far
        self.walking: str | None = None          # why the robot walks on to search, if it does
        self.start = self.seen = 0.0             # s: started, person last seen
        self.close_since = self.near_since = 0.0   # s: came close / near (target distance)
        self.faces = 0                           # frames of the followed person with a face
        self.turn, self.reversed = 1.0, -math.inf   # search turn: counter-clockwise first
        self.spot: tuple[float, float] | None = None   # where the followed person stands
        self.detours = 0                         # detours taken for the followed person

    @property
    def now(self) -> float:
        """Simulated time (s)."""
        return self.ctx.now

    def emit(self, kind: str, **fields: object) -> None:
        """Log an event tagged with the approach's name."""
        self.ctx.events.emit(kind, behaviour=self.name, **fields)

    def setup(self) -> None:
        """The controllers, and the detour planner's two occupancy grids of the floor map."""
        self.steer.setup()
        self.pid = make_pid(self.cfg.approach.pid, self.cfg.approach.max_speed)
        self.detour = Detour(self.ctx)
        self.search = Search(self.ctx, self.detour)
        self.front = PersonFront(self.cfg)

    def reset(self) -> None:
        """A new approach: nothing followed, nothing ignored, no detour."""
        self.steer.reset()
        self.pid.reset()
        self.start = self.now
        self.lose_person()
        self.escape.reset()
        self.turn, self.reversed = 1.0, -math.inf
        self.ignored.clear()
        self.spot = None
        self.detour.cancel()
        self.search.turned, self.walking = 0.0, None
        self.detours = 0
        self.front.forget()

    def towards(self, bearing: float) -> None:
        """Look for the person towards world ``bearing`` (rad) first: the search turns that
        way, and a box seen there is followed at once."""
        self.steer.look_towards(bearing)
        self.turn = math.copysign(1.0, wrap_angle(bearing - self.pose()[2]))

    def lose_person(self) -> None:
        """Forget the followed person's sightings: unseen, neither close nor near, no face."""
        self.seen = self.close_since = self.near_since = -math.inf
        self.faces = 0

    def pose(self) -> tuple[float, float, float]:
        """Where the base stands."""
        return self.ctx.robot.base.pose()

    def command(self, vx: float, vy: float, wz: float) -> None:
        """Drive (robot frame) until the next fresh frame."""
        self.steer.command(vx, vy, wz)

    def avoid(self, vx: float, wz: float) -> tuple[float, float, float]:
        """The (vx, vy, wz) command: the controllers' own, or the :class:`Escape` under way."""
        return self.escape.command(self.now, self.ctx.robot.base.blocked, vx, wz)

    def shows_face(self, person: Detection) -> bool:
        """Whether this frame shows the face of ``person`` (:func:`has_face` with the face
        regions of a whole box and of one cut off by the frame's bottom)."""
        face = self.cfg.face
        return has_face(person, self.detections, face.region, face.min_conf,
                        self.bb.frame.shape[0] - CUT_PX, face.cut_region)

    def ignore(self, heading: float) -> None:
        """Ignore the followed person's spot (or, not located, a spot 1 m along their world
        ``heading``) for ``give_up.ignore_s``."""
        x, y, _ = self.pose()
        spot = self.spot or (x + math.cos(heading), y + math.sin(heading))
        self.ignored.add(spot, self.now)
        self.spot = None

    def start_detour(self, person: Detection, front: float | None = None,
                     to_front: bool = False) -> bool:
        """Plan a detour when the map has furniture between the robot and the person, or,
        ``to_front``, because they look away from the robot; either way towards the spot
        nearest their ``front`` when the facing model has read it. Whether one started."""
        spot = self.steer.locate(person)
        x, y, _ = self.pose()
        if spot is None or not (to_front or self.detour.obstructed((x, y), spot)):
            return False
        path = self.detour.start((x, y), spot, front)
        if path is None:
            return False
        self.detours += 1
        self.front.forget()   # read their facing afresh from where the detour ends
        self.emit("detour", person=[round(v, 2) for v in spot],
                  waypoints=[[round(a, 2), round(b, 2)] for a, b in path],
                  front_deg=None if front is None else round(math.degrees(front), 1))
        return True

    def drive_detour(self) -> Status:
        """Follow the detour. Once it is over (or the base is blocked on it), the robot
        faces where the person was estimated, and the visual approach goes on from there.
        RUNNING."""
        robot = self.ctx.robot
        command = None if robot.base.blocked else self.detour.command(robot.base.pose())
        if command is not None:
            self.command(*command)
            return Status.RUNNING
        self.detour.cancel()
        if self.detour.target is not None:
            x, y, _ = robot.base.pose()
            tx, ty = self.detour.target
            self.steer.look_towards(math.atan2(ty - y, tx - x))
            self.seen = self.now
        self.walking = None
        self.command(0.0, 0.0, 0.0)
        return Status.RUNNING
