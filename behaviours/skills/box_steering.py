"""Steering by the detector's person boxes, shared by find people's approach and its
keeping them centred: the followed person's track, the heading PID, fresh-frame
bookkeeping, the face test, and the decorator that points the head for them
(docs/find_people.md). Each owner asks Sense for camera frames at its own rate (blackboard
``tracking``)."""

from __future__ import annotations

import math

import py_trees
from py_trees.common import Status
from simple_pid import PID

from behaviours.config import FindPeopleConfig, PidGains
from behaviours.context import Context
from behaviours.person_range import PersonRange
from perception.detector.yolo import Detection

HOLD_PERIODS = 1.5  # by default, without a fresh frame for this many camera periods the base stops


def make_pid(gains: PidGains, limit: float) -> PID:
    """A simple-pid controller driving its input to 0, output clamped to +-``limit``; it is
    called with the time between frames, so it runs on simulated time."""
    return PID(gains.kp, gains.ki, gains.kd, setpoint=0.0, sample_time=None,
               output_limits=(-limit, limit))


def has_face(person: Detection, detections: list[Detection], region: float,
             min_conf: float, cut_below: float = math.inf, cut_region: float = 0.0) -> bool:
    """Whether a confident face box is centred inside the upper ``region`` of ``person``;
    of a box that reaches ``cut_below`` (the frame's bottom row: only the head and
    shoulders show, as of a seated person the robot looks up at), inside its upper
    ``cut_region``."""
    x0, y0, x1, y1 = person.box
    share = cut_region if y1 >= cut_below else region
    for d in detections:
        cx, cy = d.centre
        if (d.cls == "face" and d.conf >= min_conf and x0 <= cx <= x1
                and y0 <= cy <= y0 + max(region, share) * person.height):
            return True
    return False


STEERING_READS = ("frame", "depth", "frame_t", "detections")   # a steering owner reads these
STEERING_WRITES = ("tracking",)                                 # ... and asks Sense for frames


class Steering:
    """Steering by a person box for the behaviour that owns it (its blackboard client reads
    ``STEERING_READS`` and writes ``STEERING_WRITES``): fresh-frame bookkeeping, the choice
    of the person to follow and the heading PID (turn rate from the box offset). While the
    owner runs, the camera takes ``rate`` frames a second; a command lasts ``hold_s``
    (default 1.5 frame periods) unless a fresh frame replaces it."""

    def __init__(self, ctx: Context, bb: py_trees.blackboard.Client, rate: float,
                 hold_s: float | None = None) -> None:
        self.ctx, self.bb = ctx, bb
        self.rate = rate
        self.cfg: FindPeopleConfig = ctx.config.find_people
        self.period = 1.0 / rate
        self.hold_s = HOLD_PERIODS * self.period if hold_s is None else hold_s
        self.heading: PID | None = None         # set in setup(), with the person range
        self.range: PersonRange | None = None
        self.tan_half_hfov = 0.0
        self._frame_t = -math.inf
        self._command_t = -math.inf
        self.track: float | None = None    # world direction of the followed person (rad)
        self.hits = 0                       # frames in which the track was seen

    @property
    def now(self) -> float:
        """Simulated time (s)."""
        return self.ctx.now

    def setup(self) -> None:
        """The heading PID and the person range (the owner's ``setup()``)."""
        self.heading = make_pid(self.cfg.follow.heading_pid,
                                self.ctx.robot.base.cfg.max_angular_speed)
        self.range = PersonRange(self.ctx.robot, self.ctx.config.perception)
        self.tan_half_hfov = 4 / 3 * self.range.tan_half_vfov

    def reset(self) -> None:
        """Start afresh (the owner's ``initialise()``): frames at ``rate``, no track."""
        self.bb.tracking = self.rate
        self.heading.reset()
        self._frame_t = -math.inf
        self._command_t = -math.inf
        self.forget()

    def fresh_detections(self) -> tuple[list[Detection], float] | None:
        """The detections of a frame not used before and the time since the previous one,
        or None (then the base is stopped once the last command is too old)."""
        t = self.bb.frame_t
        if self.bb.frame is None or t <= self._frame_t:
            if self.now - self._command_t > self.hold_s:
                self.ctx.robot.base.stop()
            return None
        dt = t - self._frame_t if math.isfinite(self._frame_t) else self.period
        self._frame_t = t
        return self.bb.detections, dt

    def command(self, vx: float, vy: float, wz: float) -> None:
        """Drive (robot frame) until the next fresh frame."""
        self.ctx.robot.base.set_velocity(vx, vy, wz)
        self._command_t = self.now

    def offset(self, box: Detection) -> float:
        """Horizontal offset of the box centre, -1 (left edge) to 1 (right edge)."""
        half = self.bb.frame.shape[1] / 2
        return (box.centre[0] - half) / half

    def bearing(self, box: Detection) -> float:
        """Direction of the box centre from the optical axis (rad, counter-clockwise)."""
        return -math.atan(self.offset(box) * self.tan_half_hfov)

    def distance(self, box: Detection) -> float | None:
        """Floor distance (m) to the person in ``box`` in the current depth frame
        (:meth:`PersonRange.distance`), or None."""
        return self.range.distance(self.bb.depth, box)

    def width_m(self, box: Detection) -> float | None:
        """How wide (m) the box is at the person's :meth:`distance`, or None."""
        reach = self.distance(box)
        if reach is None:
            return None
        return (box.box[2] - box.box[0]) / self.bb.frame.shape[1] * 2 * reach * self.tan_half_hfov

    def locate(self, box: Detection) -> tuple[float, float] | None:
        """Floor position of the person in ``box``: :meth:`distance` along the box centre's
        direction, or None."""
        reach = self.distance(box)
        if reach is None:
            return None
        x, y, yaw = self.ctx.robot.base.pose()
        heading = yaw + self.bearing(box)
        return x + reach * math.cos(heading), y + reach * math.sin(heading)

    def follow(self, detections: list[Detection],
               ignored: tuple[float, ...] = ()) -> Detection | None:
        """The person box to follow, or None; updates the track (the followed person's
        world direction, from the robot's heading plus the box's bearing, so turning does
        not move it) and ``hits``, the frames in which it was seen.

        A box counts when its conf reaches ``perception.min_conf``, or ``keep_conf`` within
        ``keep_gap_deg`` of the track (hysteresis: a person seen side-on is not dropped). It
        must reach within ``bottom_margin_px`` of the image's bottom edge (at ``head_pitch``
        every standing or seated adult's box does), be no taller than a person at its
        distance can be (:meth:`plausible`), and its direction must not lie within
        ``ignore_width_deg`` of an ``ignored`` one (rad). The best ``conf - gap to the
        track (rad)`` wins."""
        cfg = self.cfg
        yaw = self.ctx.robot.base.pose()[2]
        bottom = self.bb.frame.shape[0] - cfg.follow.bottom_margin_px

        def direction(d: Detection) -> float:
            return yaw + self.bearing(d)

        def gap(d: Detection, to: float | None) -> float:
            return math.inf if to is None else abs(math.remainder(direction(d) - to, math.tau))

        def score(d: Detection) -> float:
            return d.conf - (0.0 if self.track is None else gap(d, self.track))

        keep = math.radians(cfg.follow.keep_gap_deg)
        boxes = [d for d in detections
                 if d.cls == "person" and d.box[3] >= bottom
                 and (d.conf >= self.ctx.config.perception.min_conf
                      or (d.conf >= cfg.follow.keep_conf and gap(d, self.track) <= keep))
                 and all(gap(d, h) > math.radians(cfg.give_up.ignore_width_deg) for h in ignored)
                 and self.range.plausible(self.bb.depth, d, self.distance(d))]
        best = max(boxes, key=score, default=None)
        if best is not None:
            self.hits = self.hits + 1 if gap(best, self.track) <= keep else 1
            self.track = direction(best)
        return best

    def look_towards(self, direction: float) -> None:
        """Expect the followed person in world ``direction`` (rad): a box found there next
        continues the track and is acted on at once."""
        self.track, self.hits = direction, self.cfg.follow.confirm_frames - 1

    def forget(self) -> None:
        """Drop the track: the next box found starts a new one."""
        self.track, self.hits = None, 0


class Tracking(py_trees.decorators.PassThrough):
    """While the child runs: head straight and pitched up to ``head.pitch``. On exit: the
    camera back at the scenario's rate (blackboard ``tracking`` 0), base stopped, head back
    where it was."""

    def __init__(self, name: str, child: py_trees.behaviour.Behaviour, ctx: Context
                 ) -> None:
        super().__init__(name, child)
        self.ctx = ctx
        self.bb = self.attach_blackboard_client(name=name)
        self.bb.register_key("tracking", access=py_trees.common.Access.WRITE)
        self._head: tuple[float, float] | None = None   # (yaw, pitch) to go back to

    def initialise(self) -> None:
        self._head = self.ctx.robot.head.targets()
        self.ctx.robot.head.look(0.0, self.ctx.config.find_people.head.pitch)

    def terminate(self, new_status: Status) -> None:
        self.bb.tracking = 0.0
        self.ctx.robot.base.stop()
        if self._head is not None:
            self.ctx.robot.head.look(*self._head)
            self._head = None
