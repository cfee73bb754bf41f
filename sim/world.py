"""The household world of a scenario, built into a PyBullet client (DIRECT mode is enough).

:class:`World` builds the floor, the walls of each room (with door gaps), furniture and
objects from primitives or ``pybullet_data`` models, the charging dock and the people, and
keeps the lighting as data for the TinyRenderer. It does not spawn the robot: it only
exposes :meth:`World.robot_start` and :meth:`World.dock_pose`.

:meth:`World.advance` plays the scenario timeline: it applies the physical events (enter,
leave, walk_to, pose) and returns the social ones (say, encourage, emotion) to the caller.
Poses returned by the world have their yaw in radians (the YAML uses degrees).
"""

from __future__ import annotations

import bisect
import math
from pathlib import Path

import pybullet as p
import pybullet_data

from robot.geometry import Footprint, Pose2D
from robot.percepts import EmotionEvent, EncourageEvent, FeedbackEvent, SayEvent, SocialEvent
from sim.furnishings import (
    DARK,
    FURNITURE_COLOURS,
    OBJECT_COLOURS,
    URDF_OBJECTS,
    furniture_parts,
    object_xml,
)
from sim.layout import Furniture, Placement, SceneObject, rgb
from sim.lighting import Light
from sim.people import (
    Appearance,
    Part,
    Person,
    Rgb,
    build_body,
    joint_xml,
    link_xml,
    load_urdf_text,
)
from sim.scenario import Event, Scenario, load_scenario
from sim.walks import Walk, give_way, short_of

WALL_THICKNESS = 0.1
PARK_X, PARK_Y = -1000.0, -1000.0   # where the bodies of people who left wait (m)
DOOR_HEIGHT = 2.05
GROUND = (0.45, 0.47, 0.45, 1.0)  # outside the rooms
CEILING: Rgb = (0.96, 0.96, 0.94)
STOP_SHORT = 0.7  # a person walking up to another stops this far from them, and a walking
                  # person who gives way keeps this far from the robot's centre
APPROACH_SPEED = 0.7  # m/s, a person asked by the robot to come closer (or to make way)
MAKE_WAY_M = 1.0  # a standing person this near the robot, asked to make way, steps back to
MADE_WAY_M = 1.5  # this far from it


# --- walls ----------------------------------------------------------------------------------


Span = tuple[float, float]


def _subtract(span: Span, cuts: list[Span]) -> list[Span]:
    """The parts of ``span`` not covered by any of ``cuts`` (1-D intervals)."""
    pieces = [span]
    for c0, c1 in cuts:
        pieces = [q for a, b in pieces for q in ((a, min(b, c0)), (max(a, c1), b))
                  if q[1] - q[0] > 1e-6]
    return pieces


# --- the world ----------------------------------------------------------------------------


def _pose(place: Placement) -> Pose2D:
    return Pose2D(place.x, place.y, math.radians(place.yaw))


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
        self._footprints: list[Footprint] = []
        self._tops: dict[str, float] = {}
        #: bodies made and removed after the world was built, in order: ("make", id, name,
        #: URDF text) and ("remove", id); a copy of the world built from the same scenario
        #: follows it with them (sim/split_render.py)
        self.journal: list[tuple] = []
        self._built = False
        p.setGravity(0, 0, -9.81, physicsClientId=client)
        self._build_house()
        for f in scenario.furniture:
            self._build_furniture(f)
        for i, o in enumerate(scenario.objects):
            self._build_object(o, o.name or f"{o.type}_{i}")
        self._build_dock()
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

    # -- building ----------------------------------------------------------------------------

    def _build_house(self) -> None:
        rooms = self.scenario.rooms
        floors = [Part("box", (r.x[1] - r.x[0], r.y[1] - r.y[0], 0.01), rgb(r.floor_colour),
                       ((r.x[0] + r.x[1]) / 2, (r.y[0] + r.y[1]) / 2, -0.005), collide=False)
                  for r in rooms]
        walls: list[Part] = []
        built: dict[tuple[str, float], list[tuple[float, float]]] = {}
        doors: dict[tuple[str, float], list[tuple[float, float]]] = {}
        for r in rooms:
            for d in r.doors:
                key, c = self._door_line(r.x, r.y, d.wall, d.offset)
                doors.setdefault(key, []).append((c - d.width / 2, c + d.width / 2))
        t = WALL_THICKNESS
        for r in rooms:
            colour, h = rgb(r.wall_colour), r.wall_height
            sides = [(("h", r.y[0]), r.x), (("h", r.y[1]), r.x), (("v", r.x[0]), r.y),
                     (("v", r.x[1]), r.y)]
            for (axis, at), (a, b) in sides:
                key = (axis, round(at, 3))
                gaps = doors.get(key, [])
                for a0, b0 in _subtract((a - t / 2, b + t / 2), gaps + built.get(key, [])):
                    walls.append(self._wall_part(axis, at, a0, b0, 0.0, h, colour))
                for g0, g1 in gaps:
                    if h > DOOR_HEIGHT + 0.05 and a < (g0 + g1) / 2 < b:
                        walls.append(self._wall_part(axis, at, g0, g1, DOOR_HEIGHT, h, colour))
                built.setdefault(key, []).append((a - t / 2, b + t / 2))
        ceilings = [Part("box", (r.x[1] - r.x[0], r.y[1] - r.y[0], 0.02), CEILING,
                         ((r.x[0] + r.x[1]) / 2, (r.y[0] + r.y[1]) / 2, r.wall_height + 0.01),
                         collide=False) for r in rooms if r.ceiling]
        xml = link_xml("floor", floors) + link_xml("walls", walls) + link_xml("ceiling", ceilings)
        xml += joint_xml("walls_joint", "floor", "walls", (0, 0, 0))
        xml += joint_xml("ceiling_joint", "floor", "ceiling", (0, 0, 0))
        self.bodies["house"] = load_urdf_text(self.client, "house", xml)

    @staticmethod
    def _door_line(x: tuple[float, float], y: tuple[float, float], wall: str,
                   offset: float) -> tuple[tuple[str, float], float]:
        """The wall line key of a door and its centre coordinate along that line."""
        if wall in ("south", "north"):
            return ("h", round(y[0] if wall == "south" else y[1], 3)), x[0] + offset
        return ("v", round(x[0] if wall == "west" else x[1], 3)), y[0] + offset

    def _wall_part(self, axis: str, at: float, a: float, b: float, z0: float, z1: float,
                   colour: Rgb) -> Part:
        mid, length, t = (a + b) / 2, b - a, WALL_THICKNESS
        if z0 == 0.0:
            self._footprints.append(Footprint(
                "wall", "wall", mid if axis == "h" else at, at if axis == "h" else mid,
                0.0, (length if axis == "h" else t) / 2, (t if axis == "h" else length) / 2))
        size = (length, t, z1 - z0) if axis == "h" else (t, length, z1 - z0)
        xyz = (mid, at, (z0 + z1) / 2) if axis == "h" else (at, mid, (z0 + z1) / 2)
        return Part("box", size, colour, xyz)

    def _build_furniture(self, f: Furniture) -> None:
        d, w, h = f.dims
        parts, top = furniture_parts(f.type, d, w, h, rgb(f.colour or FURNITURE_COLOURS[f.type]))
        yaw = math.radians(f.yaw)
        self.bodies[f.name] = build_body(self.client, f.name, parts, (f.x, f.y, 0), yaw)
        self._tops[f.name] = top
        self._footprints.append(Footprint(f.name, "furniture", f.x, f.y, yaw, d / 2, w / 2))

    def _build_object(self, o: SceneObject, name: str) -> None:
        x, y, z = o.x, o.y, 0.0
        if o.on_top_of is not None:
            base = next(f for f in self.scenario.furniture if f.name == o.on_top_of)
            x, y = (base.x if x is None else x), (base.y if y is None else y)
            z = self._tops[o.on_top_of]
        assert x is not None and y is not None  # guaranteed by the scenario checks
        yaw = math.radians(o.yaw)
        if o.type in URDF_OBJECTS:
            file, scale, roll = URDF_OBJECTS[o.type]
            body = p.loadURDF(str(Path(pybullet_data.getDataPath()) / file), (0, 0, 0),
                              p.getQuaternionFromEuler((roll, 0, yaw)), useFixedBase=True,
                              globalScaling=scale * o.scale, physicsClientId=self.client)
            if o.colour is not None:
                p.changeVisualShape(body, -1, rgbaColor=(*rgb(o.colour), 1),
                                    physicsClientId=self.client)
        else:
            colour = rgb(o.colour or OBJECT_COLOURS[o.type])
            body = load_urdf_text(self.client, name, object_xml(o, colour), (0, 0, 0), yaw)
        (x0, y0, z0), (x1, y1, _) = p.getAABB(body, -1, physicsClientId=self.client)
        pos, orn = p.getBasePositionAndOrientation(body, physicsClientId=self.client)
        p.resetBasePositionAndOrientation(
            body, (x + pos[0] - (x0 + x1) / 2, y + pos[1] - (y0 + y1) / 2, z + pos[2] - z0),
            orn, physicsClientId=self.client)
        self.bodies[name] = body
        if o.on_top_of is None:
            self._footprints.append(Footprint(name, "object", x, y, 0.0, (x1 - x0) / 2,
                                              (y1 - y0) / 2))

    def _build_dock(self) -> None:
        """A dark pad with yellow edges and a back plate carrying a cyan-cross marker.

        The dock pose is where the robot stands when docked, facing the plate (+x locally).
        """
        yellow, white, cyan = (0.95, 0.8, 0.1), (0.95, 0.95, 0.95), (0.0, 0.85, 0.9)
        plate_x = 0.38
        parts = [Part("box", (0.7, 0.6, 0.02), (0.2, 0.2, 0.22), (0, 0, 0.01), collide=False),
                 *[Part("box", (0.7, 0.05, 0.024), yellow, (0, s * 0.3, 0.012), collide=False)
                   for s in (1, -1)],
                 Part("box", (0.04, 0.5, 0.45), white, (plate_x, 0, 0.245)),
                 Part("box", (0.006, 0.32, 0.32), DARK, (plate_x - 0.023, 0, 0.27), collide=False),
                 Part("box", (0.006, 0.24, 0.06), cyan, (plate_x - 0.027, 0, 0.27), collide=False),
                 Part("box", (0.006, 0.06, 0.24), cyan, (plate_x - 0.027, 0, 0.27), collide=False)]
        dock = self.dock_pose()
        self.bodies["dock"] = build_body(self.client, "dock", parts, (dock.x, dock.y, 0), dock.yaw)
        c, s = math.cos(dock.yaw), math.sin(dock.yaw)
        self._footprints.append(Footprint("dock", "dock", dock.x + c * plate_x,
                                          dock.y + s * plate_x, dock.yaw, 0.02, 0.25))

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
                    (axis, at), c = self._door_line(r.x, r.y, d.wall, d.offset)
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
        return not any(f.contains(*at) for f in self._footprints if f.kind != "dock")

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

    def dock_pose(self) -> Pose2D:
        """Where the robot stands when docked, facing the dock's marker plate."""
        return _pose(self.scenario.dock)

    def robot_start(self) -> Pose2D:
        """The robot's start pose (the caller spawns the robot there)."""
        return _pose(self.scenario.robot.start)

    def furniture_top(self, name: str) -> float:
        """Height (m) of the top of the furniture item ``name`` (KeyError: no such item)."""
        return self._tops[name]

    def room_at(self, x: float, y: float) -> str | None:
        """The name of the room holding ``(x, y)``, or None (a wall, outside)."""
        return next((r.name for r in self.scenario.rooms if r.contains(x, y, 0.0)), None)

    def room_bounds(self) -> dict[str, tuple[float, float, float, float]]:
        """``(x_min, y_min, x_max, y_max)`` of each room, by name."""
        return {r.name: (r.x[0], r.y[0], r.x[1], r.y[1]) for r in self.scenario.rooms}

    def obstacles(self, include_people: bool = False) -> list[Footprint]:
        """Floor footprints of walls, furniture, floor objects and the dock plate (and people)."""
        out = list(self._footprints)
        if include_people:
            for name, person in self.people.items():
                (x0, y0, _), (x1, y1, _) = person.aabb()
                out.append(Footprint(name, "person", (x0 + x1) / 2, (y0 + y1) / 2, 0.0,
                                     (x1 - x0) / 2, (y1 - y0) / 2))
        return out
