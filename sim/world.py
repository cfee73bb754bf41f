"""The household world of a scenario, built into a PyBullet client (DIRECT mode is enough).

:class:`World` builds the floor, the walls of each room (with door gaps), furniture and
objects from primitives or ``pybullet_data`` models, the charging dock and the people, and
keeps the lighting as data for the TinyRenderer. It does not spawn the robot: it only
exposes :meth:`World.robot_start` and, through its :class:`~sim.house.House`, the dock.

:meth:`World.advance` plays the scenario timeline: it applies the physical events (enter,
leave, walk_to, pose) and returns the social ones (say, encourage, emotion) to the caller.
Poses returned by the world have their yaw in radians (the YAML uses degrees).
"""

from __future__ import annotations

import bisect
import math
from pathlib import Path

import pybullet as p

from robot.geometry import Footprint, Pose2D
from robot.percepts import EmotionEvent, EncourageEvent, FeedbackEvent, SayEvent, SocialEvent
from sim.house import House, door_line, pose_of
from sim.layout import rgb
from sim.lighting import Light
from sim.people import (
    Appearance,
    Part,
    Person,
    link_xml,
    load_urdf_text,
)
from sim.scenario import Event, Scenario, load_scenario
from sim.walks import Walk, give_way, short_of

PARK_X, PARK_Y = -1000.0, -1000.0   # where the bodies of people who left wait (m)
GROUND = (0.45, 0.47, 0.45, 1.0)  # outside the rooms
STOP_SHORT = 0.7  # a person walking up to another stops this far from them, and a walking
                  # person who gives way keeps this far from the robot's centre
APPROACH_SPEED = 0.7  # m/s, a person asked by the robot to come closer (or to make way)
MAKE_WAY_M = 1.0  # a standing person this near the robot, asked to make way, steps back to
MADE_WAY_M = 1.5  # this far from it


# --- the world ----------------------------------------------------------------------------




class World:
    """A scenario's household in a PyBullet client: static scene, people and their timeline."""

    def __init__(self, scenario: Scenario, client: int) -> None:
        self.scenario = scenario
        self.client = client
        s = scenario.lighting
        self.light = Light(s.direction, rgb(s.colour), s.ambient, s.diffuse, s.specular,
                           s.shadows)
        self.bodies: dict[str, int] = {}
        self.people: dict[str, Person] = {}
        self.expressions: dict[str, str] = {}   # what each person's face shows
        self._specs = {person.name: person for person in scenario.people}
        self._walks: dict[str, Walk] = {}
        self._parked: dict[str, Person] = {}   # bodies of people who left, kept for their return
        #: bodies made and removed after the world was built, in order: ("make", id, name,
        #: URDF text) and ("remove", id); a copy of the world built from the same scenario
        #: follows it with them (sim/split_render.py)
        self.journal: list[tuple] = []
        self._built = False
        p.setGravity(0, 0, -9.81, physicsClientId=client)
        #: the static scene, the robot's map of its home (sim/house.py)
        self.house = House(scenario, client, self.bodies)
        for spec in scenario.people:
            if spec.start is not None:
                self._spawn(spec.name, spec.start.x, spec.start.y, math.radians(spec.start.yaw),
                            spec.start.pose)
        # The ground last: the camera's renderer shades a pixel only when it is nearer than
        # what is drawn there already, and from inside the house little ground is seen.
        ground = p.createVisualShape(p.GEOM_BOX, halfExtents=(50, 50, 0.005),
                                     visualFramePosition=(0, 0, -0.01), rgbaColor=GROUND,
                                     physicsClientId=client)
        self.bodies["ground"] = p.createMultiBody(
            0, p.createCollisionShape(p.GEOM_PLANE, physicsClientId=client), ground,
            physicsClientId=client)
        self.pass_through(self.bodies["ground"])
        self._built = True
        # In time order; at equal times people enter first (others may walk up to them).
        self._timeline = sorted(((e.at, spec.name, e) for spec in scenario.people
                                 for e in spec.events), key=lambda i: (i[0], i[2].kind != "enter"))
        self._times = [t for t, _, _ in self._timeline]

    @classmethod
    def from_file(cls, path: str | Path, client: int) -> World:
        """Load the scenario at ``path`` and build it into ``client``."""
        return cls(load_scenario(path), client)

    # -- people and the timeline ----------------------------------------------------------------

    def _spawn(self, name: str, x: float, y: float, yaw: float, pose: str = "standing") -> None:
        if name in self._parked:   # back again: the same body (PyBullet never frees a shape)
            person = self.people[name] = self._parked.pop(name)
            person.set_pose(pose)  # type: ignore[arg-type]
            person.place(x, y, yaw)
            return
        b = self._specs[name].body
        look = Appearance(b.height, b.width, rgb(b.shirt), rgb(b.trousers), rgb(b.skin),
                          rgb(b.hair))
        person = self.people[name] = Person(self.client, look, x, y, yaw, pose, name)  # type: ignore[arg-type]
        if self._built:
            self.journal.append(("make", person.body_id, name, person.urdf))
        for i in range(p.getNumBodies(physicsClientId=self.client)):
            other = p.getBodyUniqueId(i, physicsClientId=self.client)
            if other != person.body_id:
                self._no_contacts(person.body_id, other)

    def _park(self, name: str) -> None:
        """Take ``name`` out of the house: their body waits far outside it, out of every
        sensor's reach, for their next entrance (a new body each time would leak memory:
        PyBullet keeps every shape it ever made)."""
        person = self.people.pop(name)
        self._walks.pop(name, None)
        person.place(PARK_X - 5.0 * len(self._parked), PARK_Y, 0.0)
        self._parked[name] = person

    def pass_through(self, body: int) -> None:
        """People, present and parked, make no contacts with ``body``, a body made after
        them (people to come are kept apart from every body there is when they come in).
        People are moved kinematically: contacts with them would only cost physics time
        (more than half of each step in the nursing home) and throw the robot's joints
        about when one walks into it. Rays, distance queries (the robot's own collision
        checks) and the camera still see them."""
        for person in [*self.people.values(), *self._parked.values()]:
            self._no_contacts(person.body_id, body)

    def _no_contacts(self, a: int, b: int) -> None:
        c = self.client
        for i in range(-1, p.getNumJoints(a, physicsClientId=c)):
            for j in range(-1, p.getNumJoints(b, physicsClientId=c)):
                p.setCollisionFilterPair(a, b, i, j, 0, physicsClientId=c)

    def _door_spawn(self, door_name: str) -> Pose2D:
        """Just inside a door, facing into its room."""
        for r in self.scenario.rooms:
            for d in r.doors:
                if d.name == door_name:
                    (axis, at), c = door_line(r.x, r.y, d.wall, d.offset)
                    nx, ny = {"south": (0, 1), "north": (0, -1), "west": (1, 0),
                              "east": (-1, 0)}[d.wall]
                    x, y = (c, at) if axis == "h" else (at, c)
                    return Pose2D(x + 0.4 * nx, y + 0.4 * ny, math.atan2(ny, nx))
        raise KeyError(door_name)

    def approach(self, name: str, t: float, target: tuple[float, float], stop_m: float,
                 speed: float = APPROACH_SPEED) -> float:
        """``name`` walks straight towards ``target`` from time ``t``, stopping ``stop_m``
        short of it and facing it (standing up first); the seconds the walk takes (0 when
        they are already that close, or not in the house)."""
        if name not in self.people:
            return 0.0
        here = self._where(name, t)
        dist = math.dist((here.x, here.y), target)
        if dist <= stop_m:
            return 0.0
        self._start_walk(name, t, here, *short_of((here.x, here.y), target, stop_m), speed)
        return (dist - stop_m) / speed

    def make_way(self, t: float, robot: tuple[float, float]) -> None:
        """The robot at ``robot`` asked for its way to be cleared at ``t``: everyone standing
        within ``MAKE_WAY_M`` of it who gives way walks straight back from it to
        ``MADE_WAY_M`` (unless a wall or furniture is there), and their walk so far ends."""
        for name, person in self.people.items():
            here = self._where(name, t)
            away = math.hypot(here.x - robot[0], here.y - robot[1])
            if (person.pose == "sitting" or not self._specs[name].gives_way
                    or away > MAKE_WAY_M or away < 1e-9):
                continue
            f = MADE_WAY_M / away
            goal = (robot[0] + f * (here.x - robot[0]), robot[1] + f * (here.y - robot[1]))
            if self._room_for_people(goal):
                self._start_walk(name, t, here, goal, here.yaw, APPROACH_SPEED)

    def _room_for_people(self, at: tuple[float, float]) -> bool:
        """Whether a person can stand at ``at``: not inside a wall, furniture or an object."""
        return not any(f.contains(*at) for f in self.house.footprints if f.kind != "dock")

    def _start_walk(self, name: str, t: float, here: Pose2D, goal: tuple[float, float],
                    yaw_end: float | None, speed: float) -> None:
        """``name`` walks from ``here`` to ``goal`` from time ``t`` (standing up first)."""
        self._walks[name] = Walk(t, (here.x, here.y), here.yaw, goal, speed, yaw_end)
        if self.people[name].pose == "sitting":
            self.people[name].set_pose("standing")

    def _where(self, name: str, t: float) -> Pose2D:
        """Where a present person is at time ``t`` (following their current walk)."""
        walk = self._walks.get(name)
        if walk is not None:
            x, y, yaw, _, _ = walk.at(t)
            return Pose2D(x, y, yaw)
        person = self.people[name]
        return Pose2D(person.x, person.y, person.yaw)

    def _apply(self, t: float, name: str, e: Event) -> SocialEvent | None:
        if e.enter is None and name not in self.people:   # gone (a fault took them away)
            return None
        if e.walk_to is not None and e.walk_to.person not in (None, *self.people):
            return None
        if e.enter is not None:
            spot = (self._door_spawn(e.enter.door) if e.enter.door is not None
                    else Pose2D(e.enter.x, e.enter.y, math.radians(e.enter.yaw)))  # type: ignore[arg-type]
            self._spawn(name, spot.x, spot.y, spot.yaw)
        elif e.leave is not None:
            self._park(name)
        elif e.walk_to is not None:
            here = self._where(name, t)
            goal = (e.walk_to.x, e.walk_to.y)
            yaw_end = None if e.walk_to.yaw is None else math.radians(e.walk_to.yaw)
            if e.walk_to.person is not None:
                other = self._where(e.walk_to.person, t)
                goal, yaw_end = short_of((here.x, here.y), (other.x, other.y), STOP_SHORT)
            self._start_walk(name, t, here, goal, yaw_end, e.walk_to.speed)  # type: ignore[arg-type]
        elif e.pose is not None:
            here = self._where(name, t)
            self._walks.pop(name, None)
            self.people[name].place(here.x, here.y, here.yaw)
            self.people[name].set_pose(e.pose)
        elif e.say is not None:
            return SayEvent(t, name, e.say.text, e.say.to)
        elif e.encourage is not None:
            return EncourageEvent(t, name, e.encourage)
        elif e.emotion is not None:
            return EmotionEvent(t, name, e.emotion)
        elif e.feedback is not None:
            return FeedbackEvent(t, name, 1 if e.feedback == "positive" else -1, e.about)
        return None

    def _play(self, t_prev: float, t_now: float, offset: float) -> list[SocialEvent]:
        """Apply the timeline's events in ``[t_prev, t_now)`` of one cycle starting at
        ``offset`` (absolute time)."""
        lo = bisect.bisect_left(self._times, t_prev)
        hi = bisect.bisect_left(self._times, t_now)
        return [ev for t, name, e in self._timeline[lo:hi]
                if (ev := self._apply(offset + t, name, e)) is not None]

    def _restart_people(self) -> None:
        """Everyone back to their start (absent ones gone): a looping timeline's new cycle."""
        for name in list(self.people):
            self._park(name)
        for spec in self.scenario.people:
            if spec.start is not None:
                self._spawn(spec.name, spec.start.x, spec.start.y, math.radians(spec.start.yaw),
                            spec.start.pose)

    def advance(self, t_prev: float, t_now: float,
                robot: tuple[float, float] | None = None) -> list[SocialEvent]:
        """Play the timeline over ``[t_prev, t_now)`` and move walkers to where they are at
        ``t_now``; return the social events due, in time order. Call it with consecutive
        intervals (0 to dt, dt to 2 dt, ...). With a ``loop_period`` the timeline starts
        again every period, everyone back at their start. Walkers who give way
        (``gives_way``) see the robot standing at ``robot``: a step that would bring them
        within ``STOP_SHORT`` of it goes round it instead, and their walk goes on from
        there."""
        period = self.scenario.loop_period
        if period is None:
            social = self._play(t_prev, t_now, 0.0)
        else:
            cycle, cycle_now = int(t_prev // period), int(t_now // period)
            if cycle_now > cycle:
                social = self._play(t_prev - cycle * period, period, cycle * period)
                self._restart_people()
                social += self._play(0.0, t_now - cycle_now * period, cycle_now * period)
            else:
                social = self._play(t_prev - cycle * period, t_now - cycle * period,
                                    cycle * period)
        for name, walk in list(self._walks.items()):
            x, y, yaw, walked, done = walk.at(t_now)
            person = self.people[name]
            if robot is not None and self._specs[name].gives_way and (
                    here := self._round_robot(name, walk, (x, y), walked, robot, t_now)):
                x, y, yaw, done = here.x, here.y, here.yaw, name not in self._walks
            person.place(x, y, yaw)
            if done:
                self._walks.pop(name, None)
                person.set_pose(person.pose)  # back from the walking gait
            else:
                person.set_gait(walked / (0.45 * person.appearance.height) * math.pi)
        return social

    def _round_robot(self, name: str, walk: Walk, there: tuple[float, float], walked: float,
                     robot: tuple[float, float], t: float) -> Pose2D | None:
        """Where ``name``, about to step to ``there`` on ``walk``, steps instead to keep clear
        of the robot at ``robot`` (:func:`sim.walks.give_way`), their walk going on from
        there at ``t``. Where their goal is that near the robot, or a wall or furniture is in
        the way round, the walk ends where they stand. None when the step keeps clear."""
        person = self.people[name]
        here = (person.x, person.y)
        side = give_way(here, there, walk.goal, robot, STOP_SHORT)
        if side is None:
            return None
        if side == here or not self._room_for_people(side):
            del self._walks[name]
            return Pose2D(*here, person.yaw)
        pose = Pose2D(*side, math.atan2(side[1] - here[1], side[0] - here[0]))
        self._start_walk(name, t, pose, walk.goal, walk.yaw_end, walk.speed)
        self._walks[name].walked0 = walked
        return pose

    # -- faults (companion run --faults) -----------------------------------------------------

    def drop_box(self, name: str, x: float, y: float, size: float = 0.45) -> None:
        """A box appears at ``(x, y)``: an obstacle the robot's floor map does not hold."""
        part = Part("box", (size, size, size), (0.6, 0.45, 0.3), (0, 0, size / 2))
        urdf = link_xml("base", [part])
        self.bodies[name] = load_urdf_text(self.client, name, urdf, (x, y, 0))
        self.journal.append(("make", self.bodies[name], name, urdf))
        self.pass_through(self.bodies[name])

    def take_away(self, name: str) -> None:
        """Remove the body ``name`` (a dropped box) or the person ``name`` at once; their
        later timeline events are skipped."""
        if name in self.people:
            self._park(name)
        else:
            body = self.bodies.pop(name)
            p.removeBody(body, physicsClientId=self.client)
            self.journal.append(("remove", body))

    # -- queries -------------------------------------------------------------------------------

    def standing_still(self, name: str) -> bool:
        """Whether person ``name`` is in the house and not walking."""
        return name in self.people and name not in self._walks

    def position_of(self, name: str) -> tuple[float, float, float]:
        """Where the furniture item or object ``name`` stands (its base, m)."""
        pos, _ = p.getBasePositionAndOrientation(self.bodies[name], physicsClientId=self.client)
        return pos

    def show_emotion(self, person: str, emotion: str) -> None:
        """``person``'s face shows ``emotion`` from now on (until they show another)."""
        self.expressions[person] = emotion

    def expression_of(self, body_id: int) -> str | None:
        """The emotion the face of the person whose body is ``body_id`` shows, or None (no
        person, or a neutral face). What an expression classifier would read off a face the
        camera sees: the caller must have found the face in a frame first."""
        for name, person in self.people.items():
            if person.body_id == body_id:
                return self.expressions.get(name)
        return None

    def people_positions(self) -> dict[str, Pose2D]:
        """Pose of every person now in the world."""
        return {name: Pose2D(q.x, q.y, q.yaw) for name, q in self.people.items()}

    def robot_start(self) -> Pose2D:
        """The robot's start pose (the caller spawns the robot there)."""
        return pose_of(self.scenario.robot.start)

    def obstacles(self, include_people: bool = False) -> list[Footprint]:
        """Floor footprints of walls, furniture, floor objects and the dock plate (and people)."""
        out = self.house.obstacles()
        if include_people:
            for name, person in self.people.items():
                (x0, y0, _), (x1, y1, _) = person.aabb()
                out.append(Footprint(name, "person", (x0 + x1) / 2, (y0 + y1) / 2, 0.0,
                                     (x1 - x0) / 2, (y1 - y0) / 2))
        return out
