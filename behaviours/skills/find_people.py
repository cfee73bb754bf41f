"""Find people: look for a person with the YOLO detector, turn to them and walk
up to them with two simple-pid loops, greet them once their face confirms they look at the
robot, and keep them centred while the action's Table 4.2 duration runs.

Only the detector's boxes on the blackboard steer the robot (no simulator ground truth):

- heading: the person box's horizontal offset from the image centre, normalised to
  [-1, 1], drives the turn rate towards 0;
- approach: the box height drives the forward speed until it reaches
  ``target_height_px`` (about 1.0 m from a standing adult, docs/find_people.md).

The controllers act once per fresh camera frame; in between the base holds its command for
up to 1.5 frame periods, then stops. docs/find_people.md describes the states and parameters.
"""

from __future__ import annotations

import math

import py_trees
from py_trees.common import ParallelPolicy, Status
from simple_pid import PID

from behaviours.config import FindPeopleConfig, PidGains
from behaviours.context import Household
from behaviours.skill import HouseholdBehaviour, Relieve, Say
from perception.detector import Detection

HOLD_PERIODS = 1.5  # without a fresh frame for this many tracking periods the base stops


def make_pid(gains: PidGains, limit: float) -> PID:
    """A simple-pid controller driving its input to 0, output clamped to +-``limit``; it is
    called with the time between frames, so it runs on simulated time."""
    return PID(gains.kp, gains.ki, gains.kd, setpoint=0.0, sample_time=None,
               output_limits=(-limit, limit))


def has_face(person: Detection, detections: list[Detection], region: float,
             min_conf: float) -> bool:
    """Whether a confident face box is centred inside the upper ``region`` of ``person``."""
    x0, y0, x1, _ = person.box
    for d in detections:
        cx, cy = d.centre
        if (d.cls == "face" and d.conf >= min_conf and x0 <= cx <= x1
                and y0 <= cy <= y0 + region * person.height):
            return True
    return False


class BoxSteering(HouseholdBehaviour):
    """Base of the leaves that steer by a person box: fresh-frame bookkeeping, the choice
    of the person to follow and the heading PID (turn rate from the box offset)."""

    def __init__(self, name: str, house: Household) -> None:
        super().__init__(name, house, reads=("frame", "frame_t", "detections"))
        self.cfg: FindPeopleConfig = house.config.find_people
        base = house.robot.cfg.base
        self.heading = make_pid(self.cfg.heading_pid, base.max_angular_speed)
        cam = house.robot.cfg.camera
        self.tan_half_hfov = 4 / 3 * math.tan(math.radians(cam.fov_deg) / 2)
        self.period = 1.0 / house.config.perception.tracking_rate
        self._frame_t = -math.inf
        self._command_t = -math.inf
        self._track: float | None = None   # world direction of the followed person (rad)
        self.hits = 0                       # frames in which the track was seen

    def initialise(self) -> None:
        self.heading.reset()
        self._frame_t = -math.inf
        self._command_t = -math.inf
        self.forget()

    def fresh_detections(self) -> tuple[list[Detection], float] | None:
        """The detections of a frame not used before and the time since the previous one,
        or None (then the base is stopped once the last command is too old)."""
        t = self.bb.frame_t
        if self.bb.frame is None or t <= self._frame_t:
            if self.now - self._command_t > HOLD_PERIODS * self.period:
                self.house.robot.stop()
            return None
        dt = t - self._frame_t if math.isfinite(self._frame_t) else self.period
        self._frame_t = t
        return self.bb.detections, dt

    def command(self, vx: float, vy: float, wz: float) -> None:
        """Drive (robot frame) until the next fresh frame."""
        self.house.robot.set_base_velocity(vx, vy, wz)
        self._command_t = self.now

    def offset(self, box: Detection) -> float:
        """Horizontal offset of the box centre, -1 (left edge) to 1 (right edge)."""
        half = self.bb.frame.shape[1] / 2
        return (box.centre[0] - half) / half

    def bearing(self, box: Detection) -> float:
        """Direction of the box centre from the optical axis (rad, counter-clockwise)."""
        return -math.atan(self.offset(box) * self.tan_half_hfov)

    def follow(self, detections: list[Detection],
               ignored: tuple[float, ...] = ()) -> Detection | None:
        """The person box to follow, or None; updates the track (the followed person's
        world direction, from the robot's heading plus the box's bearing, so turning does
        not move it) and ``hits``, the frames in which it was seen.

        A box counts when its conf reaches ``perception.min_conf``, or ``keep_conf`` within
        ``keep_gap_deg`` of the track (hysteresis: a person seen side-on is not dropped). It
        must reach within ``bottom_margin_px`` of the image's bottom edge (at ``head_pitch``
        every standing or seated adult's box does), and its direction must not lie within
        ``ignore_width_deg`` of an ``ignored`` one (rad). The best ``conf - gap to the
        track (rad)`` wins."""
        cfg = self.cfg
        yaw = self.house.robot.pose()[2]
        bottom = self.bb.frame.shape[0] - cfg.bottom_margin_px

        def direction(d: Detection) -> float:
            return yaw + self.bearing(d)

        def gap(d: Detection, to: float | None) -> float:
            return math.inf if to is None else abs(math.remainder(direction(d) - to, math.tau))

        def score(d: Detection) -> float:
            return d.conf - (0.0 if self._track is None else gap(d, self._track))

        keep = math.radians(cfg.keep_gap_deg)
        boxes = [d for d in detections
                 if d.cls == "person" and d.box[3] >= bottom
                 and (d.conf >= self.house.config.perception.min_conf
                      or (d.conf >= cfg.keep_conf and gap(d, self._track) <= keep))
                 and all(gap(d, h) > math.radians(cfg.ignore_width_deg) for h in ignored)]
        best = max(boxes, key=score, default=None)
        if best is not None:
            self.hits = self.hits + 1 if gap(best, self._track) <= keep else 1
            self._track = direction(best)
        return best

    def forget(self) -> None:
        """Drop the track: the next box found starts a new one."""
        self._track, self.hits = None, 0

    def terminate(self, new_status: Status) -> None:
        self.house.robot.stop()


class ApproachPerson(BoxSteering):
    """Search (turn in place), centre and approach a person until their box is
    ``target_height_px`` tall. SUCCESS there once their face has been seen in
    ``face_frames`` frames since the robot began to follow them (their front is turned to
    it). Blocked on the way (the base reports it), the robot backs up and sidesteps. A
    person whose face has not shown enough ``face_wait_s`` after the robot came near (their
    back is turned, or it is no person) is ignored for ``ignore_s``. FAILURE after
    ``timeout_s``."""

    def __init__(self, house: Household, name: str = "Approach a person") -> None:
        super().__init__(name, house)
        self.approach = make_pid(self.cfg.approach_pid, self.cfg.max_approach_speed)
        self._start = self._seen = self._near_since = 0.0   # s: started, person last seen, near
        self._faces = 0                          # frames of the followed person with a face
        self._side, self._escape_start = 1.0, -math.inf   # sidestep to the left first
        self._ignored: dict[float, float] = {}   # world heading (rad) -> ignored until (s)

    def initialise(self) -> None:
        super().initialise()
        self.approach.reset()
        self._start = self.now
        self._seen = self._near_since = -math.inf
        self._faces = 0
        self._side, self._escape_start = 1.0, -math.inf
        self._ignored = {}

    def update(self) -> Status:
        if self.now - self._start >= self.cfg.timeout_s:
            self.emit("find_failed", after_s=self.now - self._start)
            return Status.FAILURE
        fresh = self.fresh_detections()
        if fresh is None:
            return Status.RUNNING
        detections, dt = fresh
        self._ignored = {h: t for h, t in self._ignored.items() if t > self.now}
        person = self.follow(detections, tuple(self._ignored))
        if person is None or self.hits < self.cfg.confirm_frames:
            self._search()
            return Status.RUNNING
        self._seen = self.now
        return self._steer(person, detections, dt)

    def _search(self) -> None:
        """No confirmed person in view: hold still while the one followed may just have
        been missed, else turn counter-clockwise. Always the same way: turning towards where
        a box was last seen lets two passing false positives bounce the robot between
        them."""
        if self.now - self._seen < self.cfg.lost_after_s:
            self.command(0.0, 0.0, 0.0)
            return
        if math.isfinite(self._seen):
            self.forget()
            self.heading.reset()
            self.approach.reset()
            self._seen = self._near_since = -math.inf
            self._faces = 0
        self.command(0.0, 0.0, self.cfg.search_turn_speed)

    def _steer(self, person: Detection, detections: list[Detection], dt: float) -> Status:
        cfg = self.cfg
        offset = self.offset(person)
        shortfall = (person.height - cfg.target_height_px) / self.bb.frame.shape[0]
        wz = self.heading(offset, dt=dt)
        vx = self.approach(shortfall, dt=dt) * max(0.0, 1.0 - abs(offset) / cfg.approach_max_offset)
        self._faces += has_face(person, detections, cfg.face_region, cfg.face_min_conf)
        near = person.height >= cfg.target_height_px - cfg.height_tolerance_px
        if near and not math.isfinite(self._near_since):
            self._near_since = self.now
        arrived = (near and abs(offset) <= cfg.centre_tolerance
                   and person.height <= cfg.target_height_px + cfg.height_tolerance_px)
        if arrived and self._faces >= cfg.face_frames:
            self.command(0.0, 0.0, 0.0)
            self.emit("person_found", box=[round(v, 1) for v in person.box],
                      bearing_deg=round(math.degrees(self.bearing(person)), 2),
                      face_frames=self._faces, after_s=round(self.now - self._start, 2))
            return Status.SUCCESS
        if near and self.now - self._near_since >= cfg.face_wait_s:
            self._give_up(person)
        elif arrived:
            self.command(0.0, 0.0, 0.0)
        else:
            self.command(*self._avoid(vx, wz))
        return Status.RUNNING

    def _give_up(self, person: Detection) -> None:
        """The person close by has not shown their face: ignore their direction for
        ``ignore_s`` and search on."""
        bearing = self.bearing(person)
        self._ignored[self.house.robot.pose()[2] + bearing] = self.now + self.cfg.ignore_s
        self.emit("no_face", bearing_deg=round(math.degrees(bearing), 2), face_frames=self._faces)
        self.forget()
        self._seen = self._near_since = -math.inf
        self._faces = 0
        self.command(0.0, 0.0, 0.0)

    def _avoid(self, vx: float, wz: float) -> tuple[float, float, float]:
        """The (vx, vy, wz) command: the controllers' own, or an escape after the base
        reported being blocked while driving forwards: back up for ``escape_back_s``, then
        step sideways for ``escape_side_s``. A blocked sidestep starts a new escape to the
        other side; the side that got through is kept for the next escape."""
        cfg, blocked = self.cfg, self.house.robot.blocked
        sidestep_from = self._escape_start + cfg.escape_back_s
        if self.now >= sidestep_from + cfg.escape_side_s:
            if not (blocked and vx > 0):
                return vx, 0.0, wz
            self._escape_start = self.now
        elif blocked and self.now > sidestep_from:
            self._side = -self._side
            self._escape_start = self.now
        if self.now < self._escape_start + cfg.escape_back_s:
            return -cfg.escape_speed, 0.0, 0.0
        return 0.0, self._side * cfg.escape_speed, 0.0


class KeepCentred(BoxSteering):
    """Turn so that the followed person stays centred (heading PID only); stand still when
    nobody is seen. RUNNING until stopped."""

    def __init__(self, house: Household, name: str = "Keep them centred") -> None:
        super().__init__(name, house)

    def update(self) -> Status:
        fresh = self.fresh_detections()
        if fresh is not None:
            detections, dt = fresh
            person = self.follow(detections)
            self.command(0.0, 0.0, self.heading(self.offset(person), dt=dt) if person else 0.0)
        return Status.RUNNING


class Tracking(py_trees.decorators.PassThrough):
    """While the child runs: camera at the tracking rate (blackboard ``tracking``), head
    straight and pitched up to ``head_pitch``. On exit: tracking off, base stopped, head
    back where it was."""

    def __init__(self, name: str, child: py_trees.behaviour.Behaviour, house: Household
                 ) -> None:
        super().__init__(name, child)
        self.house = house
        self.bb = self.attach_blackboard_client(name=name)
        self.bb.register_key("tracking", access=py_trees.common.Access.WRITE)
        self._head: dict[str, float] = {}

    def initialise(self) -> None:
        self.bb.tracking = True
        targets = self.house.robot.joint_targets()
        self._head = {j: targets[j] for j in ("HeadYaw", "HeadPitch")}
        self.house.robot.move_joints(
            {"HeadYaw": 0.0, "HeadPitch": self.house.config.find_people.head_pitch}, 1.0)

    def terminate(self, new_status: Status) -> None:
        self.bb.tracking = False
        self.house.robot.stop()
        if self._head:
            self.house.robot.move_joints(self._head, 1.0)
            self._head = {}


def build(house: Household) -> py_trees.behaviour.Behaviour:
    """The find-people subtree: approach a person, then greet them and relieve the
    belonging drive while keeping them centred."""
    greet_then_relieve = py_trees.composites.Sequence(
        "Greet and stay", memory=True,
        children=[Say("Greet", house, house.config.find_people.greet),
                  Relieve("Belonging relieves", house, "find_people")])
    together = py_trees.composites.Parallel(
        "With the person", policy=ParallelPolicy.SuccessOnOne(),
        children=[greet_then_relieve, KeepCentred(house)])
    steps = py_trees.composites.Sequence("Find people steps", memory=True,
                                         children=[ApproachPerson(house), together])
    return Tracking("Find people", steps, house)
