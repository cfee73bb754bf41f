"""Find people: look for a person with the YOLO detector, turn to them and walk
up to them with two simple-pid loops, greet them once their face confirms they look at the
robot, and keep them centred while the action's Table 4.2 duration runs.

Only the detector's boxes on the blackboard steer the robot (no simulator ground truth):

- heading: the person box's horizontal offset from the image centre, normalised to
  [-1, 1], drives the turn rate towards 0;
- approach: the person's distance, read from the head camera's depth image inside their
  box, drives the forward speed until it reaches ``target_distance_m`` (their body centre
  then stands about 1.0 m away, whether they stand or sit; docs/find_people.md).

The controllers act once per fresh camera frame; in between the base holds its command for
up to 1.5 frame periods, then stops. Close to the person the robot counts frames with their
face and circles them when it has not seen enough; docs/find_people.md describes the
states and parameters. The shared steering pieces live in ``box_steering.py``.
"""

from __future__ import annotations

import math
from typing import Any

import py_trees
from py_trees.common import Access, ParallelPolicy, Status
from simple_pid import PID

from behaviours.context import Context
from behaviours.skill import Relieve, Say, facing_of
from behaviours.skills.box_steering import BoxSteering, Tracking, has_face, make_pid
from behaviours.skills.detour import Detour
from behaviours.skills.person_front import PersonFront
from behaviours.skills.search import Search, remember
from behaviours.skills.setbacks import Escape, Ignored
from perception.detector.yolo import Detection

CUT_PX = 2   # a person box reaching this close to the frame's bottom is cut off there


class ApproachPerson(BoxSteering):
    """Search (turn in place), centre and approach a person until they are
    ``target_distance_m`` away. SUCCESS there once their face has been seen in
    ``face_frames`` frames since the robot began to follow them (their front is turned to
    it). Furniture on the map between them: the robot takes a planned detour (:class:`Detour`);
    blocked by anything else (the base reports it), it backs up and sidesteps. If the
    face count is short ``face_wait_s`` after the robot came near, it circles the person
    to see their front; a person whose face still has not shown (their back is turned, or
    it is no person), or a near box without a face that keeps vanishing, is ignored for
    ``ignore_s``: boxes towards where they stand. Having looked all the way round without
    finding anyone, it walks on to search elsewhere (:class:`~behaviours.skills.search.
    Search`), watching for people on the way. FAILURE after ``timeout_s``."""

    def __init__(self, ctx: Context, name: str = "Approach a person") -> None:
        super().__init__(name, ctx, ctx.config.perception.tracking_rate)
        for key in ("people_seen", "rooms_searched"):
            self.bb.register_key(key, access=Access.WRITE)
        self.bb.register_key("facings", access=Access.READ)
        self.approach: PID | None = None          # set in setup(), with the detour planner
        self.detour: Detour | None = None
        self.search: Search | None = None
        self._walking: str | None = None         # why the robot walks on to search, if it does
        self._start = self._seen = 0.0           # s: started, person last seen
        self._close_since = self._near_since = 0.0   # s: came close / near (target distance)
        self._faces = 0                          # frames of the followed person with a face
        self.escape = Escape(self.cfg)           # backing up and stepping aside
        self._turn, self._reversed = 1.0, -math.inf   # search turn: counter-clockwise first
        # floor spot of a person given up on -> ignored until (s)
        self.ignored = Ignored(self.cfg)
        self._spot: tuple[float, float] | None = None   # where the followed person stands
        self._detours = 0                        # detours taken for the followed person
        self.front: PersonFront | None = None   # which way they face (set in setup())

    def setup(self, **kwargs: Any) -> None:
        super().setup(**kwargs)
        self.approach = make_pid(self.cfg.approach_pid, self.cfg.max_approach_speed)
        self.detour = Detour(self.ctx)   # two occupancy grids of the floor map
        self.search = Search(self.ctx, self.detour)
        self.front = PersonFront(self.cfg)

    def initialise(self) -> None:
        super().initialise()
        self.approach.reset()
        self._start = self.now
        self._seen = self._close_since = self._near_since = -math.inf
        self._faces = 0
        self.escape.reset()
        self._turn, self._reversed = 1.0, -math.inf
        self.ignored.clear()
        self._spot = None
        self.detour.cancel()
        self.search.turned, self._walking = 0.0, None
        self._detours = 0
        self.front.forget()

    def update(self) -> Status:
        if self.now - self._start >= self.cfg.timeout_s:
            self.emit("find_failed", after_s=self.now - self._start)
            return Status.FAILURE
        fresh = self.fresh_detections()
        if fresh is None:
            return Status.RUNNING
        detections, dt = fresh
        self.ignored.expire(self.now)
        if self.detour.active and self._walking is None:
            return self._drive_detour()
        x, y, _ = self.ctx.robot.base.pose()
        person = self.follow(detections, self.ignored.headings_from(x, y))
        if person is None or self.hits < self.cfg.confirm_frames:
            if self.detour.active:
                return self._drive_detour()
            self._search(dt)
            return Status.RUNNING
        spot = self.locate(person)
        if spot is not None and self._implausible(person, detections, spot):
            self.ignored.add(spot, self.now)
            self.forget()
            return self._drive_detour() if self.detour.active else Status.RUNNING
        if self._walking is not None:   # someone in view on the way: approach them
            self.detour.cancel()
            self._walking = None
        self._seen = self.now
        self.search.turned = 0.0   # a look round counts from the last person seen
        self._spot = spot or self._spot
        if self._spot is not None:
            self.bb.people_seen = remember(self.bb.people_seen, self._spot, self.now,
                                           self.cfg.sightings_kept)
        return self._steer(person, detections, dt)

    def _search(self, dt: float) -> None:
        """No confirmed person in view: hold still while the one followed may just have
        been missed, else turn counter-clockwise. Always the same way: turning towards where
        a box was last seen lets two passing false positives bounce the robot between
        them. Only a turn the base refuses (an arm against a table) is reversed, and one
        refused both ways within a full turn (wedged) starts the escape of :meth:`_avoid`.
        Once the turns add up to a look all the way round, walk on (:meth:`_walk_on`)."""
        if self.now - self._seen < self.cfg.lost_after_s:
            self.command(0.0, 0.0, 0.0)
            return
        if math.isfinite(self._seen):
            if math.isfinite(self._close_since) and self._faces < self.cfg.face_frames:
                self._count_vanished()
            self._detours = 0
            self._spot = None
            self.front.forget()
            self.forget()
            self.heading.reset()
            self.approach.reset()
            self._seen = self._close_since = self._near_since = -math.inf
            self._faces = 0
        vx, vy, wz = self.ctx.robot.base.velocity
        if self.ctx.robot.base.blocked and vx == vy == 0.0 and wz * self._turn > 0:
            if self.now - self._reversed < math.tau / self.cfg.search_turn_speed:
                self.escape.begin(self.now)
            self._turn, self._reversed = -self._turn, self.now
        if self.search.turn(wz, dt) and self._walk_on():
            return
        self.command(*self._avoid(0.0, self._turn * self.cfg.search_turn_speed))

    def _shows_face(self, person: Detection, detections: list[Detection]) -> bool:
        """Whether this frame shows the face of ``person`` (:func:`has_face` with the face
        regions of a whole box and of one cut off by the frame's bottom)."""
        cfg = self.cfg
        return has_face(person, detections, cfg.face_region, cfg.face_min_conf,
                        self.bb.frame.shape[0] - CUT_PX, cfg.cut_face_region)

    def _implausible(self, person: Detection, detections: list[Detection],
                     spot: tuple[float, float]) -> bool:
        """Whether the confirmed box cannot be a person: wider than ``max_person_width_m``
        at its distance (the detector's false positives on a wall seen at a grazing angle),
        or located in a wall of the map without a face in it (a corner of the room; a
        person seated against a wall, whose torso depth reaches the wall, shows their face
        when the robot can greet them at all). Logged as ``not_a_person``."""
        width = self.width_m(person)
        wall = self.search.on_wall(spot) and not self._shows_face(person, detections)
        if not wall and (width is None or width <= self.cfg.max_person_width_m):
            return False
        self.emit("not_a_person", spot=[round(v, 2) for v in spot], on_wall=wall,
                  width_m=None if width is None else round(width, 2))
        return True

    def _walk_on(self) -> bool:
        """Nobody to greet all the way round: note this room as searched in vain and walk
        to where to search next; whether the robot walks."""
        x, y, _ = self.ctx.robot.base.pose()
        room = self.search.room_of((x, y))
        if room is not None:
            self.bb.rooms_searched = {**self.bb.rooms_searched, room: self.now}
        choice = self.search.go_on((x, y), self.now, self.bb.people_seen,
                                   self.bb.rooms_searched, self.ignored.spots())
        if choice is None:
            return False
        self._walking, goal = choice
        self.bb.people_seen = [s for s in self.bb.people_seen
                               if math.dist(s[:2], goal) >= 0.5]   # looked for there now
        self.emit("search_on", why=self._walking, searched=room,
                  goal=[round(v, 2) for v in goal])
        return True

    def _steer(self, person: Detection, detections: list[Detection], dt: float) -> Status:
        cfg = self.cfg
        offset = self.offset(person)
        dist = self.distance(person)
        shortfall = 0.0 if dist is None else cfg.target_distance_m - dist   # > 0: too close
        wz = self.heading(offset, dt=dt)
        vx = self.approach(shortfall, dt=dt) * max(0.0, 1.0 - abs(offset) / cfg.approach_max_offset)
        self._pitch_to(person, dist)
        self._faces += self._shows_face(person, detections)
        # Close: at most about the target distance away. Near: about at it. Closer (the
        # person stepped up to the robot, their head may be cut off by the frame), the
        # approach loop backs off; the face wait, circling and giving up start once the
        # robot is near, or after `backoff_s` of being close without getting near (backing
        # off is blocked).
        close = shortfall >= -cfg.distance_tolerance_m and dist is not None
        near = close and shortfall <= cfg.distance_tolerance_m
        if not close and self._across(dist):   # a table between: greet from here
            close = near = True
            vx = min(vx, 0.0)
        if close and not math.isfinite(self._close_since):
            self._close_since = self.now
        if near and not math.isfinite(self._near_since):
            self._near_since = self.now
        arrived = near and abs(offset) <= cfg.centre_tolerance
        near_at = self._near_since if math.isfinite(self._near_since) else math.inf
        face_clock = min(near_at, self._close_since + cfg.backoff_s)
        waited = max(0.0, self.now - face_clock) if close else 0.0
        x, y, _ = self.ctx.robot.base.pose()
        seen = facing_of(self.bb.detections, self.bb.facings, person)
        reading = self.front.read(seen, self.locate(person), dist, (x, y))
        if (reading is not None and self._faces < cfg.face_frames
                and self._detours < cfg.max_detours and self._to_front(reading[1], waited)
                and self._start_detour(person, reading[0], to_front=True)):
            return self._drive_detour()
        if arrived and self._faces >= cfg.face_frames:
            self.command(0.0, 0.0, 0.0)
            self.emit("person_found", box=[round(v, 1) for v in person.box],
                      bearing_deg=round(math.degrees(self.bearing(person)), 2),
                      face_frames=self._faces, after_s=round(self.now - self._start, 2))
            return Status.SUCCESS
        if waited >= cfg.face_wait_s + 3 * cfg.orbit_s:
            self._give_up(person)
        elif waited >= cfg.face_wait_s:
            self.command(vx, self._orbit(waited) * cfg.orbit_speed, wz)
        elif arrived:
            self.command(0.0, 0.0, 0.0)
        elif (not (close or self._detours >= cfg.max_detours)
              and self._start_detour(person, self.front.guess())):
            return self._drive_detour()
        else:
            self.command(*self._avoid(vx, wz))
        return Status.RUNNING

    def _pitch_to(self, person: Detection, dist: float | None) -> None:
        """Look level at a seated person close by: within ``seated_distance_m``, their box
        cut off by the frame's bottom with its top below ``seated_box_top`` of the frame
        (the head pitched up for standing people puts a seated face at the bottom edge).
        The head goes back to ``head_pitch`` once a box's top reaches the frame's top."""
        height = self.bb.frame.shape[0]
        pitch = None
        if person.box[1] <= CUT_PX:
            pitch = self.cfg.head_pitch
        elif (dist is not None and dist <= self.cfg.seated_distance_m
              and person.box[3] >= height - CUT_PX
              and person.box[1] >= self.cfg.seated_box_top * height):
            pitch = self.cfg.seated_head_pitch
        if pitch is not None:
            self.ctx.robot.joints.move({"HeadPitch": pitch}, 1.0)

    def _across(self, dist: float | None) -> bool:
        """Whether the followed person is within ``greet_max_m`` and the map leaves the
        robot no room nearer them on this side (a table between them)."""
        if dist is None or dist > self.cfg.greet_max_m or self._spot is None:
            return False
        x, y, _ = self.ctx.robot.base.pose()
        return not self.detour.can_stand_near((x, y), self._spot)

    def _to_front(self, turned: float, waited: float) -> bool:
        """Whether to go round to the person's front: they look more than ``away_deg`` away
        from the robot (their face cannot show from here), or, near them with no face for
        ``face_wait_s``, more than ``front_tolerance_deg`` away."""
        cfg = self.cfg
        return (turned > math.radians(cfg.away_deg)
                or (waited >= cfg.face_wait_s and turned > math.radians(cfg.front_tolerance_deg)))

    def _start_detour(self, person: Detection, front: float | None = None,
                      to_front: bool = False) -> bool:
        """Plan a detour when the map has furniture between the robot and the person, or,
        ``to_front``, because they look away from the robot; either way towards the spot
        nearest their ``front`` when the facing model has read it."""
        spot = self.locate(person)
        x, y, _ = self.ctx.robot.base.pose()
        if spot is None or not (to_front or self.detour.obstructed((x, y), spot)):
            return False
        path = self.detour.start((x, y), spot, front)
        if path is None:
            return False
        self._detours += 1
        self.front.forget()   # read their facing afresh from where the detour ends
        self.emit("detour", person=[round(v, 2) for v in spot],
                  waypoints=[[round(a, 2), round(b, 2)] for a, b in path],
                  front_deg=None if front is None else round(math.degrees(front), 1))
        return True

    def _drive_detour(self) -> Status:
        """Follow the detour. Once it is over (or the base is blocked on it), the robot
        faces where the person was estimated, and the visual approach goes on from there."""
        robot = self.ctx.robot
        command = None if robot.base.blocked else self.detour.command(robot.base.pose())
        if command is not None:
            self.command(*command)
            return Status.RUNNING
        self.detour.cancel()
        if self.detour.target is not None:
            x, y, _ = robot.base.pose()
            tx, ty = self.detour.target
            self.look_towards(math.atan2(ty - y, tx - x))
            self._seen = self.now
        self._walking = None
        self.command(0.0, 0.0, 0.0)
        return Status.RUNNING

    def _count_vanished(self) -> None:
        """The near box of the followed track vanished before its face was confirmed; after
        ``vanish_strikes`` times in one direction, ignore that direction (a person close
        by stays in view; a false positive on furniture flickers)."""
        count = self.ignored.vanished_at(self._track)
        if count is None:
            return
        self._ignore(self._track)
        self.emit("no_face", bearing_deg=round(math.degrees(math.remainder(
            self._track - self.ctx.robot.base.pose()[2], math.tau)), 2),
            face_frames=self._faces, vanished=count)

    def _orbit(self, waited: float) -> float:
        """Sideways direction while looking for the person's front: left for ``orbit_s``,
        then right for twice that (back past the start), both PIDs still running, so the
        robot circles the person at the target distance."""
        return 1.0 if waited < self.cfg.face_wait_s + self.cfg.orbit_s else -1.0

    def _ignore(self, heading: float) -> None:
        """Ignore the followed person's spot (or, not located, a spot 1 m along their world
        ``heading``) for ``ignore_s``."""
        x, y, _ = self.ctx.robot.base.pose()
        spot = self._spot or (x + math.cos(heading), y + math.sin(heading))
        self.ignored.add(spot, self.now)
        self._spot = None

    def _give_up(self, person: Detection) -> None:
        """The person close by has not shown their face: ignore where they are for
        ``ignore_s`` and search on."""
        bearing = self.bearing(person)
        self._ignore(self.ctx.robot.base.pose()[2] + bearing)
        self.emit("no_face", bearing_deg=round(math.degrees(bearing), 2), face_frames=self._faces)
        self.forget()
        self._seen = self._close_since = self._near_since = -math.inf
        self._faces = 0
        self.command(0.0, 0.0, 0.0)

    def _avoid(self, vx: float, wz: float) -> tuple[float, float, float]:
        """The (vx, vy, wz) command: the controllers' own, or the :class:`Escape` under way."""
        return self.escape.command(self.now, self.ctx.robot.base.blocked, vx, wz)


class KeepCentred(BoxSteering):
    """Turn so that the followed person stays centred (heading PID only); stand still when
    nobody is seen. RUNNING until stopped. Frames come less often than while approaching,
    so each turn command lasts one approach frame period only: the heading PID then corrects
    the same share of the error per frame as it does there, instead of overshooting."""

    def __init__(self, ctx: Context, name: str = "Keep them centred") -> None:
        perception = ctx.config.perception
        super().__init__(name, ctx, perception.centring_rate,
                         hold_s=1.0 / perception.tracking_rate)

    def update(self) -> Status:
        fresh = self.fresh_detections()
        if fresh is not None:
            detections, dt = fresh
            person = self.follow(detections)
            self.command(0.0, 0.0, self.heading(self.offset(person), dt=dt) if person else 0.0)
        return Status.RUNNING


def build(ctx: Context) -> py_trees.behaviour.Behaviour:
    """The find-people subtree: approach a person, then greet them and relieve the
    belonging drive while keeping them centred."""
    greet_then_relieve = py_trees.composites.Sequence(
        "Greet and stay", memory=True,
        children=[Say("Greet", ctx, ctx.config.find_people.greet),
                  Relieve("Belonging relieves", ctx, "find_people")])
    together = py_trees.composites.Parallel(
        "With the person", policy=ParallelPolicy.SuccessOnOne(),
        children=[greet_then_relieve, KeepCentred(ctx)])
    steps = py_trees.composites.Sequence("Find people steps", memory=True,
                                         children=[ApproachPerson(ctx), together])
    return Tracking("Find people", steps, ctx)
