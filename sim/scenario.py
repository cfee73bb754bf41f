"""Household scenarios: the validated YAML format of ``worlds/*.yaml`` (docs/scenarios.md).

:func:`load_scenario` parses a file safely, validates it against :class:`Scenario` (unknown
keys are errors), then runs the cross-field checks of :func:`scenario_problems` and loads
the personality file. Every problem is reported with its path, e.g.
``people[2].events[0].at: Input should be greater than or equal to 0``.

Conventions: metres and seconds; x east, y north; yaw in DEGREES in the YAML (0 = facing +x,
90 = facing +y); colours as ``"#rrggbb"``.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Literal

from pydantic import Field, create_model, model_validator

from core.config_files import ConfigError, StrictModel, read_yaml, validate
from core.limits import MAX_DURATION_S, SEED_MAX
from mind.personality import DRIVES, Action, load_personality
from mind.preferences.config import TasteLists
from robot.forecast import Weather
from robot.percepts import AUDIENCES
from robot.voices import PEOPLE_VOICES, Voice, VoiceError, check_voice
from sim.layout import (
    ROOM_MARGIN,
    Colour,
    Furniture,
    Placement,
    PoseName,
    Room,
    SceneObject,
    Unit,
)
from sim.scenario_space import PERSON_RADIUS, ROBOT_RADIUS, overlaps


class Body(StrictModel):
    """How a person looks: height and shoulder width in metres, and colours."""

    height: float = Field(default=1.7, ge=0.9, le=2.1)
    width: float = Field(default=0.45, ge=0.25, le=0.7)
    shirt: Colour = "#3366bb"
    trousers: Colour = "#333340"
    skin: Colour = "#deb08f"
    hair: Colour = "#40291a"


class Start(Placement):
    """Where a person is at time 0, and in which pose."""

    pose: PoseName = "standing"


class Enter(StrictModel):
    """Appear at a door (just inside it, facing in) or at a position."""

    door: str | None = None
    x: float | None = None
    y: float | None = None
    yaw: float = 0.0

    @model_validator(mode="after")
    def _where(self) -> Enter:
        if (self.door is None) == (self.x is None or self.y is None):
            raise ValueError("give either `door` or both `x` and `y`")
        return self


class WalkTo(StrictModel):
    """Walk in a straight line to a point, or up to another person (stopping short of them)."""

    x: float | None = None
    y: float | None = None
    person: str | None = None
    speed: float = Field(default=0.8, gt=0, le=2.5)
    yaw: float | None = None  # heading on arrival; default: keep the walking direction

    @model_validator(mode="after")
    def _where(self) -> WalkTo:
        if (self.person is None) == (self.x is None or self.y is None):
            raise ValueError("give either `person` or both `x` and `y`")
        return self


class Say(StrictModel):
    """A line the person says: to ``robot`` (default), ``everyone`` or another person's name."""

    text: str = Field(min_length=1)
    to: str = "robot"

    @model_validator(mode="before")
    @classmethod
    def _from_text(cls, data: Any) -> Any:
        return {"text": data} if isinstance(data, str) else data


PHYSICAL = ("enter", "leave", "walk_to", "pose")
SOCIAL = ("say", "encourage", "emotion", "feedback")


class Event(StrictModel):
    """One timed action of a person: exactly one of the action keys besides ``at``."""

    at: float = Field(ge=0)
    enter: Enter | None = None
    leave: Literal[True] | None = None
    walk_to: WalkTo | None = None
    pose: PoseName | None = None
    say: Say | None = None
    encourage: str | None = Field(default=None, min_length=1)
    emotion: Literal["happy", "sad", "neutral"] | None = None
    feedback: Literal["positive", "negative"] | None = None   # r_external (docs/feedback.md)
    about: Action | None = None    # with feedback: the action it is about

    @model_validator(mode="after")
    def _one_action(self) -> Event:
        given = [k for k in (*PHYSICAL, *SOCIAL) if getattr(self, k) is not None]
        if len(given) != 1:
            raise ValueError(f"an event needs exactly one of {', '.join((*PHYSICAL, *SOCIAL))};"
                             f" got {given or 'none'}")
        if self.about is not None and self.feedback is None:
            raise ValueError("about: only a feedback event says what it is about")
        return self

    @property
    def kind(self) -> str:
        """The action key this event uses (``enter``, ``say``, ...)."""
        return next(k for k in (*PHYSICAL, *SOCIAL) if getattr(self, k) is not None)


class Tastes(TasteLists):
    """What a person thinks of the robot's actions, and says so when they see one in the
    same room (sim/reactions.py): ``likes`` get praise, ``dislikes`` a scolding."""

    chance: float = Field(default=1.0, ge=0, le=1)   # of reacting to each action they see
    after_s: float = Field(default=8.0, gt=0, le=3600)  # seconds into the action
    distance_m: float = Field(default=6.0, gt=0, le=100)  # at most this far from the robot


class PersonSpec(StrictModel):
    """A person: looks, where they are at the start (absent if no ``start``), timed events,
    and tastes for what the robot does."""

    name: str = Field(min_length=1)
    body: Body = Body()
    start: Start | None = None
    events: tuple[Event, ...] = ()
    tastes: Tastes = Tastes()
    voice: Voice | None = None   # espeak-ng voice of their lines; None: one by their place
    repeat_if_asked: bool = True  # say a line again when the robot asks them to
    gives_way: bool = True   # walking, they go round the robot rather than into it


InitialDrives = create_model(  # one optional field per drive name, each in [0, 1]
    "InitialDrives", __base__=StrictModel, __doc__="Drive values at time 0 (default 0).",
    **{d: (Unit, 0.0) for d in DRIVES})


class Robot(StrictModel):
    """The robot's start pose, battery charge and initial drives (the robot is not spawned)."""

    start: Placement
    battery: Unit = 1.0
    drives: InitialDrives = InitialDrives()  # type: ignore[valid-type]

    @model_validator(mode="after")
    def _energy_is_battery(self) -> Robot:
        # One quantity: the energy drive is the battery's emptiness (docs/behaviours.md).
        if ("energy" in self.drives.model_fields_set
                and abs(self.drives.energy - (1.0 - self.battery)) > 0.02):
            raise ValueError(f"drives.energy: {self.drives.energy} contradicts battery "
                             f"{self.battery}; the energy drive is 1 - battery (leave it out)")
        return self

    def initial_drives(self) -> dict[str, float]:
        """Drives at time 0, with energy = 1 - battery."""
        return {**self.drives.model_dump(), "energy": 1.0 - self.battery}


class Lighting(StrictModel):
    """TinyRenderer light: direction (towards the light), colour and shading coefficients."""

    direction: tuple[float, float, float] = (0.4, -0.3, 1.0)
    colour: Colour = "#ffffff"
    ambient: Unit = 0.6
    diffuse: Unit = 0.35
    specular: Unit = 0.05
    shadows: bool = False


class Scenario(StrictModel):
    """A household scenario (see docs/scenarios.md for every key)."""

    name: str
    description: str = ""
    seed: int = Field(default=0, ge=0, le=SEED_MAX)
    duration: float = Field(gt=0, le=MAX_DURATION_S)
    loop_period: float | None = Field(default=None, gt=0)  # people's timelines repeat (s)
    step: float = Field(default=0.1, gt=0, le=1)
    camera_rate: float = Field(default=1.0, gt=0, le=30)
    time_of_day: str = Field(default="10:00", pattern=r"^([01]\d|2[0-3]):[0-5]\d$")
    occasion: str = "quiet_afternoon"   # what is going on (docs/scenarios.md)
    staff: bool = False   # care staff to call (a care home); else the robot turns to family
    personality: Path | None = None
    lighting: Lighting = Lighting()
    rooms: tuple[Room, ...] = Field(min_length=1)
    furniture: tuple[Furniture, ...] = ()
    objects: tuple[SceneObject, ...] = ()
    dock: Placement
    robot: Robot
    people: tuple[PersonSpec, ...] = ()
    weather: Weather | None = None

    @model_validator(mode="after")
    def _rates(self) -> Scenario:
        if self.step > self.duration:
            raise ValueError("step must not exceed duration")
        if self.camera_rate * self.step > 1 + 1e-9:
            raise ValueError("camera_rate cannot exceed one frame per step (1 / step)")
        return self

    def in_rooms(self, x: float, y: float, margin: float = ROOM_MARGIN) -> bool:
        """Whether ``(x, y)`` is inside some room, at least ``margin`` from its walls."""
        return any(room.contains(x, y, margin) for room in self.rooms)


def _duplicates(names: list[str]) -> set[str]:
    return {n for n in names if names.count(n) > 1}


def _layout_problems(s: Scenario) -> list[str]:
    out: list[str] = []
    for kind, names in (("rooms", [r.name for r in s.rooms]),
                        ("doors", [d.name for r in s.rooms for d in r.doors]),
                        ("furniture and objects", [f.name for f in s.furniture]
                         + [o.name for o in s.objects if o.name]),
                        ("people", [p.name for p in s.people])):
        out += [f"{kind}: name {n!r} is used more than once" for n in sorted(_duplicates(names))]
    where = [("dock", s.dock), ("robot.start", s.robot.start)]
    where += [(f"furniture[{i}]", f) for i, f in enumerate(s.furniture)]
    where += [(f"people[{i}].start", p.start) for i, p in enumerate(s.people) if p.start]
    where += [(f"objects[{i}]", o) for i, o in enumerate(s.objects) if o.on_top_of is None]
    out += [f"{path}: ({w.x:g}, {w.y:g}) is outside the rooms" for path, w in where
            if not s.in_rooms(w.x, w.y, 0.0)]  # type: ignore[arg-type]
    out += [f"people: {n!r} is reserved for who a line is said to; pick another name"
            for n in AUDIENCES if n in {p.name for p in s.people}]
    furniture = {f.name: f for f in s.furniture}
    out += [f"rooms[{i}].noise.source: no furniture named {r.noise.source!r}"
            for i, r in enumerate(s.rooms)
            if r.noise.source is not None and r.noise.source not in furniture]
    for i, o in enumerate(s.objects):
        base = furniture.get(o.on_top_of) if o.on_top_of else None
        if o.on_top_of is not None and base is None:
            out.append(f"objects[{i}].on_top_of: no furniture named {o.on_top_of!r}")
        elif base is not None and o.x is not None and o.y is not None \
                and not base.covers(o.x, o.y):
            out.append(f"objects[{i}]: ({o.x:g}, {o.y:g}) is not on top of {base.name!r}")
        if o.candles and o.type != "cake":
            out.append(f"objects[{i}].candles: only a cake has candles")
    return out


def _presence(person: PersonSpec) -> list[tuple[float, bool]]:
    """(time, present afterwards) for each enter/leave of ``person``, in order."""
    return [(e.at, e.enter is not None) for e in person.events if e.kind in ("enter", "leave")]


def _present(person: PersonSpec, t: float) -> bool:
    here = person.start is not None
    for at, after in _presence(person):
        if at <= t:
            here = after
    return here


def _other_person(e: Event) -> tuple[str, str] | None:
    """(key, name) when the event refers to another person."""
    if e.walk_to is not None and e.walk_to.person is not None:
        return "walk_to.person", e.walk_to.person
    if e.say is not None and e.say.to not in AUDIENCES:
        return "say.to", e.say.to
    return None


def _target_problem(s: Scenario, path: str, e: Event) -> str | None:
    """Whether an enter or walk_to position is outside the rooms."""
    doors = {d.name for r in s.rooms for d in r.doors}
    if e.enter is not None and e.enter.door is not None:
        return None if e.enter.door in doors else f"{path}.enter.door: no door named " \
            f"{e.enter.door!r}"
    spot = e.enter or e.walk_to
    if spot is None or spot.x is None or spot.y is None or s.in_rooms(spot.x, spot.y):
        return None
    return (f"{path}.{e.kind}: ({spot.x:g}, {spot.y:g}) is not inside a room "
            f"(at least {ROOM_MARGIN} m from the walls)")


def _event_problems(s: Scenario) -> list[str]:
    out: list[str] = []
    people = {p.name: p for p in s.people}
    for i, person in enumerate(s.people):
        here, last = person.start is not None, 0.0
        for j, e in enumerate(person.events):
            path = f"people[{i}].events[{j}]"
            end = s.loop_period or s.duration
            if e.at >= end:
                what = "its loop_period" if s.loop_period else "the end of the scenario (duration"
                out.append(f"{path}.at: {e.at:g} s is not before {what} {end:g} s"
                           + ("" if s.loop_period else ")"))
            if e.at < last:
                out.append(f"{path}.at: events must be in time order ({e.at:g} < {last:g})")
            last = max(last, e.at)
            if (e.kind == "enter") == here:
                state = "already" if here else "not"
                out.append(f"{path}.{e.kind}: {person.name} is {state} in the world at {e.at:g} s")
            here = (here or e.kind == "enter") and e.kind != "leave"
            if (problem := _target_problem(s, path, e)) is not None:
                out.append(problem)
            if (ref := _other_person(e)) is not None:
                key, other = ref
                if other not in people or other == person.name:
                    out.append(f"{path}.{key}: no other person named {other!r}")
                elif not _present(people[other], e.at):
                    out.append(f"{path}.{key}: {other} is not in the world at {e.at:g} s")
    return out


def _start_problems(s: Scenario) -> list[str]:
    """Robot, dock or people starting inside a wall or furniture (sim/scenario_space.py)."""
    out = overlaps(s.rooms, s.furniture, "robot.start", s.robot.start, ROBOT_RADIUS)
    out += overlaps(s.rooms, s.furniture, "dock", s.dock, ROBOT_RADIUS)
    for i, p in enumerate(s.people):
        if p.start is not None:
            out += overlaps(s.rooms, s.furniture, f"people[{i}].start", p.start, PERSON_RADIUS,
                            seated=p.start.pose == "sitting")
    return out


def voice_of(s: Scenario, name: str) -> Voice:
    """The voice person ``name`` speaks with: their own, or one of
    :data:`robot.voices.PEOPLE_VOICES` by their place in the scenario's list."""
    i, person = next((i, p) for i, p in enumerate(s.people) if p.name == name)
    return person.voice or PEOPLE_VOICES[i % len(PEOPLE_VOICES)]


def _voice_problems(s: Scenario) -> list[str]:
    """Voices espeak-ng does not have."""
    out = []
    for i, p in enumerate(s.people):
        if p.voice is not None:
            try:
                check_voice(p.voice)
            except VoiceError as exc:
                out.append(f"people[{i}].voice: {exc}")
    return out


def scenario_problems(s: Scenario) -> list[str]:
    """Cross-field problems of a schema-valid scenario, each as ``path: message``."""
    return (_layout_problems(s) + _start_problems(s) + _event_problems(s)
            + _voice_problems(s))


def load_scenario(path: str | Path) -> Scenario:
    """Load and fully check ``path``; ``personality`` comes back as a resolved absolute path."""
    path = Path(path)
    scenario = validate(Scenario, read_yaml(path), str(path))
    problems = scenario_problems(scenario)
    if scenario.personality is not None:
        resolved = (path.parent / scenario.personality).resolve()
        if not resolved.is_file():
            why = "not a file" if resolved.exists() else "file not found"
            problems.append(f"personality: {why}: {resolved}")
        else:
            try:
                load_personality(resolved)
            except ConfigError as exc:
                problems += [f"personality: {p}" for p in exc.problems]
            scenario = scenario.model_copy(update={"personality": resolved})
    if problems:
        raise ConfigError(str(path), problems)
    return scenario
