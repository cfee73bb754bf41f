"""The phases of find people's approach, as the leaves of its tree (docs/find_people.md).

Every camera frame the approach's tree picks one phase, in this order of priority: keep
driving a detour under way; with nobody confirmed in view, search (turn in place, then walk
on); drop a box that cannot be a person; then, closing in on a confirmed person, go round to
their front when they look away, greet them once their face has shown, give up on them,
circle them, wait for their face, take a detour round furniture, or walk up to them. A
leaf whose phase does not apply fails, so the selector above it tries the next; the one that
acts is RUNNING (or, for a person found, SUCCESS). The leaves share one
:class:`~behaviours.skills.approach.Approach`; they log their events under its name.
"""

from __future__ import annotations

import math

import py_trees
from py_trees.common import Status

from behaviours.skill import facing_of
from behaviours.skills.approach import CUT_PX, Approach, Closing
from behaviours.skills.search import remember
from perception.detector.yolo import Detection


class Phase(py_trees.behaviour.Behaviour):
    """A leaf of the approach: it acts on the shared :class:`Approach` (``a``)."""

    def __init__(self, name: str, approach: Approach) -> None:
        super().__init__(name)
        self.a = approach


class WithinTime(Phase):
    """FAILURE (``find_failed``) once the approach has run ``timeout_s``, else SUCCESS."""

    def update(self) -> Status:
        a = self.a
        if a.now - a.start >= a.cfg.timeout_s:
            a.emit("find_failed", after_s=a.now - a.start)
            return Status.FAILURE
        return Status.SUCCESS


class FreshFrame(Phase):
    """SUCCESS with a camera frame not used before (its detections on the approach), else
    RUNNING (the base stops once its last command is too old)."""

    def update(self) -> Status:
        a = self.a
        fresh = a.steer.fresh_detections()
        if fresh is None:
            return Status.RUNNING
        a.detections, a.dt = fresh
        a.ignored.expire(a.now)
        return Status.SUCCESS


class OnDetour(Phase):
    """A detour to a person under way: drive it (RUNNING); else FAILURE."""

    def update(self) -> Status:
        a = self.a
        if a.detour.active and a.walking is None:
            return a.drive_detour()
        return Status.FAILURE


class FollowBox(Phase):
    """Pick the person box to follow this frame (none towards ignored spots); SUCCESS."""

    def update(self) -> Status:
        a = self.a
        x, y, _ = a.pose()
        a.person = a.steer.follow(a.detections, a.ignored.headings_from(x, y))
        return Status.SUCCESS


class Searching(Phase):
    """Nobody confirmed in view: walk on to the next place to search while doing so, else
    turn in place (:meth:`turn_round`); RUNNING. FAILURE with a confirmed person."""

    def update(self) -> Status:
        a = self.a
        if a.person is not None and a.steer.hits >= a.cfg.follow.confirm_frames:
            return Status.FAILURE
        if a.detour.active:
            return a.drive_detour()
        self.turn_round()
        return Status.RUNNING

    def turn_round(self) -> None:
        """Hold still while the one followed may just have been missed, else turn
        counter-clockwise. Always the same way: turning towards where a box was last seen
        lets two passing false positives bounce the robot between them. Only a turn the base
        refuses (an arm against a table) is reversed, and one refused both ways within a
        full turn (wedged) starts an escape. Once the turns add up to a look all the way
        round, walk on (:meth:`walk_on`)."""
        a, search = self.a, self.a.cfg.search
        if a.now - a.seen < search.lost_after_s:
            a.command(0.0, 0.0, 0.0)
            return
        if math.isfinite(a.seen):
            self.drop_person()
        base = a.ctx.robot.base
        vx, vy, wz = base.velocity
        if base.blocked and vx == vy == 0.0 and wz * a.turn > 0:
            if a.now - a.reversed < math.tau / search.turn_speed:
                a.escape.begin(a.now)
            a.turn, a.reversed = -a.turn, a.now
        if a.search.turn(wz, a.dt) and self.walk_on():
            return
        a.command(*a.avoid(0.0, a.turn * search.turn_speed))

    def drop_person(self) -> None:
        """The followed person is lost: start afresh with the next box (counting a near box
        that vanished before its face showed, :meth:`count_vanished`)."""
        a = self.a
        if math.isfinite(a.close_since) and a.faces < a.cfg.face.frames:
            self.count_vanished()
        a.detours = 0
        a.spot = None
        a.front.forget()
        a.steer.forget()
        a.steer.heading.reset()
        a.pid.reset()
        a.lose_person()

    def count_vanished(self) -> None:
        """The near box of the followed track vanished before its face was confirmed; after
        ``vanish_strikes`` times in one direction, ignore that direction (a person close
        by stays in view; a false positive on furniture flickers)."""
        a = self.a
        count = a.ignored.vanished_at(a.steer.track)
        if count is None:
            return
        a.ignore(a.steer.track)
        a.emit("no_face", bearing_deg=round(math.degrees(math.remainder(
            a.steer.track - a.pose()[2], math.tau)), 2), face_frames=a.faces, vanished=count)

    def walk_on(self) -> bool:
        """Nobody to greet all the way round: note this room as searched in vain and walk
        to where to search next; whether the robot walks."""
        a = self.a
        x, y, _ = a.pose()
        room = a.search.room_of((x, y))
        if room is not None:
            a.bb.rooms_searched = {**a.bb.rooms_searched, room: a.now}
        choice = a.search.go_on((x, y), a.now, a.bb.people_seen, a.bb.rooms_searched,
                                a.ignored.spots())
        if choice is None:
            return False
        a.walking, goal = choice
        a.bb.people_seen = [s for s in a.bb.people_seen
                            if math.dist(s[:2], goal) >= 0.5]   # looked for there now
        a.emit("search_on", why=a.walking, searched=room, goal=[round(v, 2) for v in goal])
        return True


class NotAPerson(Phase):
    """The confirmed box cannot be a person: ignore its spot, forget it (RUNNING, driving
    on a walk under way). FAILURE for a plausible box."""

    def update(self) -> Status:
        a = self.a
        spot = a.steer.locate(a.person)
        if spot is None or not self.implausible(a.person, spot):
            return Status.FAILURE
        a.ignored.add(spot, a.now)
        a.steer.forget()
        return a.drive_detour() if a.detour.active else Status.RUNNING

    def implausible(self, person: Detection, spot: tuple[float, float]) -> bool:
        """Whether the box is wider than ``max_person_width_m`` at its distance (the
        detector's false positives on a wall seen at a grazing angle), or located in a wall
        of the map without a face in it (a corner of the room; a person seated against a
        wall, whose torso depth reaches the wall, shows their face when the robot can greet
        them at all). Logged as ``not_a_person``."""
        a = self.a
        width = a.steer.width_m(person)
        wall = a.search.on_wall(spot) and not a.shows_face(person)
        if not wall and (width is None or width <= a.cfg.follow.max_person_width_m):
            return False
        a.emit("not_a_person", spot=[round(v, 2) for v in spot], on_wall=wall,
               width_m=None if width is None else round(width, 2))
        return True


class Measure(Phase):
    """A confirmed person in view: note where they stand, run both PID loops on their box,
    count their face, and say how the approach stands (``closing``); SUCCESS."""

    def update(self) -> Status:
        a = self.a
        person = a.person
        spot = a.steer.locate(person)
        if a.walking is not None:   # someone in view on the way: approach them
            a.detour.cancel()
            a.walking = None
        a.seen = a.now
        a.search.turned = 0.0   # a look round counts from the last person seen
        a.spot = spot or a.spot
        if a.spot is not None:
            a.bb.people_seen = remember(a.bb.people_seen, a.spot, a.now,
                                        a.cfg.search.sightings_kept)
        a.closing = self.closing(person)
        return Status.SUCCESS

    def closing(self, person: Detection) -> Closing:
        """The controllers' commands and the approach's standing for this frame. Close: at
        most about the target distance away. Near: about at it. Closer (the person stepped
        up to the robot, their head may be cut off by the frame), the approach loop backs
        off; the face wait starts once the robot is near, or after ``backoff_s`` of being
        close without getting near (backing off is blocked)."""
        a, cfg = self.a, self.a.cfg
        offset = a.steer.offset(person)
        dist = a.steer.distance(person)
        shortfall = 0.0 if dist is None else cfg.approach.target_distance_m - dist  # > 0: too close
        wz = a.steer.heading(offset, dt=a.dt)
        vx = a.pid(shortfall, dt=a.dt) * max(0.0, 1.0 - abs(offset) / cfg.approach.max_offset)
        self.pitch_to(person, dist)
        a.faces += a.shows_face(person)
        tolerance = cfg.approach.distance_tolerance_m
        close = shortfall >= -tolerance and dist is not None
        near = close and shortfall <= tolerance
        if not close and self.across(dist):   # a table between: greet from here
            close = near = True
            vx = min(vx, 0.0)
        if close and not math.isfinite(a.close_since):
            a.close_since = a.now
        if near and not math.isfinite(a.near_since):
            a.near_since = a.now
        near_at = a.near_since if math.isfinite(a.near_since) else math.inf
        face_clock = min(near_at, a.close_since + cfg.approach.backoff_s)
        x, y, _ = a.pose()
        seen = facing_of(a.bb.detections, a.bb.facings, person)
        return Closing(vx=vx, wz=wz, close=close,
                       arrived=near and abs(offset) <= cfg.follow.centre_tolerance,
                       waited=max(0.0, a.now - face_clock) if close else 0.0,
                       reading=a.front.read(seen, a.steer.locate(person), dist, (x, y)))

    def pitch_to(self, person: Detection, dist: float | None) -> None:
        """Look level at a seated person close by: within ``seated_distance_m``, their box
        cut off by the frame's bottom with its top below ``seated_box_top`` of the frame
        (the head pitched up for standing people puts a seated face at the bottom edge).
        The head goes back to ``head.pitch`` once a box's top reaches the frame's top."""
        head, height = self.a.cfg.head, self.a.bb.frame.shape[0]
        pitch = None
        if person.box[1] <= CUT_PX:
            pitch = head.pitch
        elif (dist is not None and dist <= head.seated_distance_m
              and person.box[3] >= height - CUT_PX
              and person.box[1] >= head.seated_box_top * height):
            pitch = head.seated_pitch
        if pitch is not None:
            self.a.ctx.robot.head.look(pitch=pitch)

    def across(self, dist: float | None) -> bool:
        """Whether the followed person is within ``greet_max_m`` and the map leaves the
        robot no room nearer them on this side (a table between them)."""
        a = self.a
        if dist is None or dist > a.cfg.detour.greet_max_m or a.spot is None:
            return False
        x, y, _ = a.pose()
        return not a.detour.can_stand_near((x, y), a.spot)


class ToFront(Phase):
    """They look away (more than ``away_deg``; or, the face wait over, more than
    ``tolerance_deg``) and their face has not shown: a detour round to their front
    (RUNNING). FAILURE otherwise, or with no detour left or possible."""

    def update(self) -> Status:
        a, cfg, c = self.a, self.a.cfg, self.a.closing
        if c.reading is None or a.faces >= cfg.face.frames or a.detours >= cfg.detour.max_detours:
            return Status.FAILURE
        turned = c.reading[1]
        away = (turned > math.radians(cfg.front.away_deg)
                or (c.waited >= cfg.face.wait_s and turned > math.radians(cfg.front.tolerance_deg)))
        if away and a.start_detour(a.person, c.reading[0], to_front=True):
            return a.drive_detour()
        return Status.FAILURE


class Found(Phase):
    """At the target distance, centred, their face seen in ``face.frames`` frames:
    ``person_found`` and SUCCESS. Else FAILURE."""

    def update(self) -> Status:
        a = self.a
        if not (a.closing.arrived and a.faces >= a.cfg.face.frames):
            return Status.FAILURE
        a.command(0.0, 0.0, 0.0)
        person = a.person
        a.emit("person_found", box=[round(v, 1) for v in person.box],
               bearing_deg=round(math.degrees(a.steer.bearing(person)), 2),
               face_frames=a.faces, after_s=round(a.now - a.start, 2))
        return Status.SUCCESS


class GiveUp(Phase):
    """The face wait and both circling legs are over without the face: ignore where the
    person is for ``ignore_s`` and search on (RUNNING). Else FAILURE."""

    def update(self) -> Status:
        a, cfg = self.a, self.a.cfg
        if a.closing.waited < cfg.face.wait_s + 3 * cfg.orbit.leg_s:
            return Status.FAILURE
        bearing = a.steer.bearing(a.person)
        a.ignore(a.pose()[2] + bearing)
        a.emit("no_face", bearing_deg=round(math.degrees(bearing), 2), face_frames=a.faces)
        a.steer.forget()
        a.lose_person()
        a.command(0.0, 0.0, 0.0)
        return Status.RUNNING


class Orbit(Phase):
    """The face wait is over: circle the person at the target distance, both PIDs still
    running, left for ``leg_s``, then right for twice that (back past the start); RUNNING.
    Else FAILURE."""

    def update(self) -> Status:
        a, cfg, c = self.a, self.a.cfg, self.a.closing
        if c.waited < cfg.face.wait_s:
            return Status.FAILURE
        side = 1.0 if c.waited < cfg.face.wait_s + cfg.orbit.leg_s else -1.0
        a.command(c.vx, side * cfg.orbit.speed, c.wz)
        return Status.RUNNING


class WaitForFace(Phase):
    """Arrived, the face not shown yet: stand still (RUNNING). Else FAILURE."""

    def update(self) -> Status:
        if not self.a.closing.arrived:
            return Status.FAILURE
        self.a.command(0.0, 0.0, 0.0)
        return Status.RUNNING


class FurnitureDetour(Phase):
    """Not close yet and furniture on the map between: a planned detour round it, to the
    side of their guessed front (RUNNING). FAILURE with none needed, left or possible."""

    def update(self) -> Status:
        a = self.a
        if (a.closing.close or a.detours >= a.cfg.detour.max_detours
                or not a.start_detour(a.person, a.front.guess())):
            return Status.FAILURE
        return a.drive_detour()


class WalkUp(Phase):
    """Drive by both PID loops (or the escape under way); RUNNING."""

    def update(self) -> Status:
        a = self.a
        a.command(*a.avoid(a.closing.vx, a.closing.wz))
        return Status.RUNNING
