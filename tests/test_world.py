"""Building scenario worlds in PyBullet DIRECT mode, the people timeline and the camera view."""

import math
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pybullet as p
import pytest

from robot.percepts import EmotionEvent, EncourageEvent, SayEvent
from sim.people import Appearance, create_person
from sim.scenario import load_scenario
from sim.world import World

WORLDS = Path(__file__).resolve().parents[1] / "worlds"
NAMES = ("living_room", "nursing_home", "birthday_party", "low_battery_night")


@pytest.fixture
def client() -> Iterator[int]:
    cid = p.connect(p.DIRECT)
    yield cid
    p.disconnect(cid)


def build(name: str, client: int) -> World:
    return World(load_scenario(WORLDS / f"{name}.yaml"), client)


def run(world: World, until: float, dt: float = 0.1, start: float = 0.0) -> list:
    """Advance in steps of ``dt`` from ``start`` to ``until``; return the social events."""
    out, k = [], 0
    while start + (k + 1) * dt <= until + 1e-9:
        out += world.advance(start + k * dt, start + (k + 1) * dt)
        k += 1
    return out


@pytest.mark.parametrize("name", NAMES)
def test_each_world_builds_and_is_consistent(name, client):
    world = build(name, client)
    s = world.scenario
    present = [q for q in s.people if q.start is not None]
    # ground, house, furniture, objects, dock, people present at the start; no robot
    expected = 3 + len(s.furniture) + len(s.objects) + len(present)
    assert p.getNumBodies(physicsClientId=client) == expected
    assert set(world.people_positions()) == {q.name for q in present}
    start, dock = world.robot_start(), world.house.dock_pose()
    assert math.isclose(start.yaw, math.radians(s.robot.start.yaw))
    assert any(x0 < dock.x < x1 and y0 < dock.y < y1
               for x0, y0, x1, y1 in world.house.room_bounds().values())
    solid = [f for f in world.obstacles() if f.kind != "dock"]
    kinds = {f.kind for f in world.obstacles()}
    assert {"wall", "furniture", "dock"} <= kinds
    for pose in (start, dock):
        assert not any(f.contains(pose.x, pose.y, margin=0.25) for f in solid), (name, pose)
    assert world.light.camera_kwargs()["lightAmbientCoeff"] == s.lighting.ambient


@pytest.mark.parametrize("name", NAMES)
def test_people_walk_around_furniture_and_every_event_fires_once(name, client):
    world = build(name, client)
    furniture = [f for f in world.obstacles() if f.kind in ("furniture", "wall")]
    before = world.people_positions()
    social, dt = [], world.scenario.step
    for k in range(round(world.scenario.duration / dt)):
        t = (k + 1) * dt
        social += world.advance(k * dt, t)
        now = world.people_positions()
        for who, pose in now.items():
            moved = who in before and math.hypot(pose.x - before[who].x, pose.y - before[who].y)
            if moved:  # a walking person never stands inside furniture or a wall
                hit = [f.name for f in furniture if f.contains(pose.x, pose.y, margin=-0.05)]
                assert not hit, (who, round(t, 1), hit)
        before = now
    n_social = sum(e.kind in ("say", "encourage", "emotion")
                   for q in world.scenario.people for e in q.events)
    assert len(social) == n_social
    assert [e.t for e in social] == sorted(e.t for e in social)


def test_living_room_timeline(client):
    world = build("living_room", client)
    bodies = p.getNumBodies(physicsClientId=client)
    events = run(world, 300.0)
    assert "Tom" not in world.people_positions()
    assert isinstance(events[0], SayEvent) and events[0].t == 15 and events[0].to == "robot"
    assert "Taipei" in events[0].text
    assert any(isinstance(e, EmotionEvent) and e.emotion == "happy" for e in events)
    assert any(isinstance(e, EncourageEvent) for e in events)

    run(world, 300.1, start=300.0)  # enters at the hall door, facing into the room
    tom = world.people_positions()["Tom"]
    assert (round(tom.x, 2), round(tom.y, 2)) == (1.0, 0.4)
    assert math.isclose(tom.yaw, math.pi / 2)
    assert p.getNumBodies(physicsClientId=client) == bodies + 1

    run(world, 303.0, start=300.1)  # walking to (2.0, 2.4) at 0.9 m/s since 302
    tom = world.people_positions()["Tom"]
    travelled = math.hypot(tom.x - 1.0, tom.y - 0.4)
    assert travelled == pytest.approx(0.9, abs=0.01)
    assert tom.yaw == pytest.approx(math.atan2(2.0, 1.0))
    run(world, 310.0, start=303.0)
    tom = world.people_positions()["Tom"]
    assert (tom.x, tom.y) == pytest.approx((2.0, 2.4))

    events = run(world, 450.0, start=310.0)  # walks up to Grace, stopping short of her
    assert [e.to for e in events if isinstance(e, SayEvent)][-1] == "Tom"
    tom, grace = world.people_positions()["Tom"], world.people_positions()["Grace"]
    assert math.hypot(tom.x - grace.x, tom.y - grace.y) == pytest.approx(0.7, abs=0.01)
    assert tom.yaw == pytest.approx(math.atan2(grace.y - tom.y, grace.x - tom.x), abs=1e-6)

    run(world, 520.0, start=450.0)  # left at 510: his body waits far outside for a return
    assert "Tom" not in world.people_positions()
    assert p.getNumBodies(physicsClientId=client) == bodies + 1


def test_step_size_does_not_change_the_story(client):
    coarse = build("birthday_party", client)
    fine_client = p.connect(p.DIRECT)
    try:
        fine = build("birthday_party", fine_client)
        a, b = run(coarse, 600.0, dt=1.0), run(fine, 600.0, dt=0.05)
        assert a == b
        here, there = coarse.people_positions(), fine.people_positions()
        assert here.keys() == there.keys()
        for name, pose in here.items():
            assert pose == pytest.approx(there[name])
    finally:
        p.disconnect(fine_client)


def test_re_entering_person_reuses_their_body(client):
    """A person who leaves waits far outside the house and comes back in the same body
    (PyBullet never frees a shape, so new bodies would grow memory in long runs)."""
    world = build("birthday_party", client)
    run(world, 430.0)
    first = world.people["Anna"]
    bodies = p.getNumBodies(physicsClientId=client)
    run(world, 440.0, start=430.0)
    assert "Anna" not in world.people
    assert min(first.x, first.y) < -100   # out of every sensor's reach
    run(world, 530.0, start=440.0)
    anna = world.people_positions()["Anna"]
    assert (anna.x, anna.y) == pytest.approx((5.0, 3.4))
    assert anna.yaw == pytest.approx(math.pi)
    assert world.people["Anna"] is first and p.getNumBodies(physicsClientId=client) == bodies


def test_pose_events_change_the_body(client):
    world = build("birthday_party", client)
    mia = world.people["Mia"]
    top = mia.aabb()[1][2]
    run(world, 50.0)
    assert mia.pose == "arms_raised" and mia.aabb()[1][2] > top + 0.15
    run(world, 70.0, start=50.0)
    assert mia.pose == "standing" and mia.aabb()[1][2] == pytest.approx(top, abs=1e-3)


def _segment(client: int, eye: tuple, target: tuple, light: dict) -> np.ndarray:
    view = p.computeViewMatrix(eye, target, (0, 0, 1))
    proj = p.computeProjectionMatrixFOV(60, 320 / 240, 0.05, 20)
    _, _, rgb, _, seg = p.getCameraImage(
        320, 240, view, proj, renderer=p.ER_TINY_RENDERER,
        flags=p.ER_SEGMENTATION_MASK_OBJECT_AND_LINKINDEX, physicsClientId=client, **light)
    assert np.asarray(rgb).reshape(240, 320, 4)[..., :3].std() > 10  # not a blank image
    return np.asarray(seg).reshape(240, 320)


def test_camera_sees_the_face_only_from_the_front(client):
    world = build("living_room", client)
    grace = world.people["Grace"]
    head = (grace.aabb()[1][2] - 0.12)
    eye, target = (grace.x + 1.6, grace.y, 1.1), (grace.x, grace.y, head)
    light = world.light.camera_kwargs()

    def pixels() -> tuple[int, int]:
        seg = _segment(client, eye, target, light)
        body, link = seg & ((1 << 24) - 1), (seg >> 24) - 1
        mine = (body == grace.body_id) & (seg >= 0)
        return int(mine.sum()), int((mine & (link == grace.face_link)).sum())

    body_px, face_px = pixels()  # Grace faces +x: towards the camera
    assert body_px > 1500 and face_px > 20
    grace.place(grace.x, grace.y, math.pi)  # turned away
    body_px, face_px = pixels()
    assert body_px > 500 and face_px == 0


def test_person_api(client):
    look = Appearance(height=1.2, width=0.3, shirt=(1, 0, 0))
    kid = create_person(client, look, 1.0, 2.0, 0.5)
    assert kid.aabb()[1][2] == pytest.approx(1.2, abs=0.01)
    assert kid.face_link == kid.links["face"] and kid.face_link >= 0
    kid.set_pose("sitting")
    assert kid.aabb()[1][2] < 1.0
    kid.place(3.0, -1.0, math.pi)
    pos, orn = p.getBasePositionAndOrientation(kid.body_id, physicsClientId=client)
    assert pos[:2] == pytest.approx((3.0, -1.0))
    assert p.getEulerFromQuaternion(orn)[2] == pytest.approx(math.pi, abs=1e-6)
    with pytest.raises(ValueError):
        kid.set_pose("dancing")  # type: ignore[arg-type]
    kid.remove()
    assert p.getNumBodies(physicsClientId=client) == 0


def test_a_person_walking_into_the_robot_leaves_its_joints_alone():
    from sim.scenario import Event, Start, WalkTo
    from sim.simulation import Simulation

    base = load_scenario(WORLDS / "living_room.yaml")
    tom = next(q for q in base.people if q.name == "Tom")
    tom = tom.model_copy(update={
        "start": Start(x=4.3, y=1.2, yaw=90.0, pose="standing"), "gives_way": False,
        "events": (Event(at=1.0, walk_to=WalkTo(x=4.3, y=4.0)),)})
    scenario = base.model_copy(update={"people": (tom,)})   # the robot stands at (4.3, 2.6)
    worst = 0.0                                                # rad from the joint targets
    with Simulation(scenario) as sim:
        while sim.t < 6.0:
            sim.step()
            measured = np.array(list(sim.robot.joints.positions().values()))
            targets = np.array(list(sim.robot.joints.targets().values()))
            worst = max(worst, float(np.abs(measured - targets).max()))
        assert sim.world.people_positions()["Tom"].y > 3.5   # Tom walked through the robot
    assert worst < 0.05


@pytest.mark.parametrize(("goal", "arrives"), [((4.3, 4.0), True), ((4.3, 3.0), False)])
def test_a_walking_person_goes_round_the_robot_or_stops_short_of_it(goal, arrives):
    from sim.scenario import Event, Start, WalkTo
    from sim.simulation import Simulation
    from sim.world import STOP_SHORT

    base = load_scenario(WORLDS / "living_room.yaml")
    tom = next(q for q in base.people if q.name == "Tom").model_copy(update={
        "start": Start(x=4.35, y=1.2, yaw=90.0, pose="standing"),
        "events": (Event(at=1.0, walk_to=WalkTo(x=goal[0], y=goal[1])),)})
    scenario = base.model_copy(update={"people": (tom,)})   # the robot stands at (4.3, 2.6)
    nearest = math.inf
    with Simulation(scenario) as sim:
        rx, ry, _ = sim.robot.base.pose()
        while sim.t < 12.0:
            sim.step()
            at = sim.world.people_positions()["Tom"]
            nearest = min(nearest, math.hypot(at.x - rx, at.y - ry))
    assert nearest >= STOP_SHORT - 1e-6            # his straight line ran through the robot
    assert math.dist((at.x, at.y), goal) < 0.01 if arrives else at.y < ry - STOP_SHORT + 0.05


def test_asked_to_clear_the_way_people_standing_near_the_robot_step_back():
    from sim.scenario import Start
    from sim.simulation import Simulation
    from sim.world import MADE_WAY_M

    base = load_scenario(WORLDS / "living_room.yaml")   # the robot stands at (4.3, 2.6)
    tom, grace = (next(q for q in base.people if q.name == n) for n in ("Tom", "Grace"))
    tom = tom.model_copy(update={"start": Start(x=4.3, y=1.8, yaw=90.0), "events": ()})
    far = grace.model_copy(update={"start": Start(x=4.3, y=4.0, yaw=-90.0), "events": ()})
    with Simulation(base.model_copy(update={"people": (tom, far)})) as sim:
        sim.ask_way()
        while sim.t < 3.0:
            sim.step()
        at = sim.world.people_positions()
    assert math.dist((at["Tom"].x, at["Tom"].y), (4.3, 2.6)) == pytest.approx(MADE_WAY_M, abs=0.01)
    assert (at["Grace"].x, at["Grace"].y) == pytest.approx((4.3, 4.0))   # too far to be asked


def test_people_make_no_contacts_yet_rays_and_distance_queries_find_them(client):
    world = build("nursing_home", client)    # four residents, two of them seated
    world.drop_box("box", 1.0, 1.0)           # made after the people
    p.stepSimulation(physicsClientId=client)
    for person in world.people.values():
        assert p.getContactPoints(person.body_id, physicsClientId=client) == ()
        hx, hy, _ = p.getLinkState(person.body_id, person.links["head"],
                                   physicsClientId=client)[0]
        down = p.rayTest((hx, hy, 2.3), (hx, hy, 0.0), physicsClientId=client)[0]
        assert down[0] == person.body_id        # a ray from above finds their head
        assert p.getClosestPoints(person.body_id, world.bodies["box"], 50.0,
                                  physicsClientId=client)


def test_a_looping_timeline_brings_everyone_back_each_period(tmp_path):
    """With loop_period, the people's events play again every period from their starts."""
    scenario = load_scenario(Path(__file__).resolve().parents[1] / "worlds" / "nursing_home.yaml")
    scenario = scenario.model_copy(update={"loop_period": scenario.duration})
    client = p.connect(p.DIRECT)
    try:
        world = World(scenario, client)
        said: list[tuple[float, str]] = []
        step, t = 0.5, 0.0
        while t < 2 * scenario.duration + 30:
            said += [(ev.t, ev.text) for ev in world.advance(t, t + step)
                     if hasattr(ev, "text")]
            t += step
            if abs(t - scenario.duration) < 1e-9:
                starts = {s.name for s in scenario.people if s.start is not None}
                assert set(world.people) == starts
        first = [text for at, text in said if at < scenario.duration]
        second = [text for at, text in said if scenario.duration <= at < 2 * scenario.duration]
        assert first and first == second
        assert all(at >= scenario.duration for at, text in said[len(first):])
    finally:
        p.disconnect(client)


def test_a_speaker_faces_whom_they_talk_to_then_turns_back():
    """People face whom they talk to (the robot's camera cue for whom a line is for): Tom
    turns to Grace for his line to her and to the robot for his line to it, each time
    turning back ``LOOK_AFTER_S`` after the line ends; Grace, walking, is not turned."""
    from robot.speaker import speech_seconds
    from sim.gaze import LOOK_AFTER_S
    from sim.scenario import Event, Start
    from sim.simulation import Simulation

    base = load_scenario(WORLDS / "living_room.yaml")   # the robot stands at (4.3, 2.6)
    tom, grace = (next(q for q in base.people if q.name == n) for n in ("Tom", "Grace"))
    to_grace, to_robot = "Would you pass the biscuits?", "What time is it?"
    tom = tom.model_copy(update={"start": Start(x=3.0, y=1.6, yaw=180.0), "events": (
        Event.model_validate({"at": 1.0, "say": {"text": to_grace, "to": "Grace"}}),
        Event.model_validate({"at": 12.0, "say": to_robot}))})
    grace = grace.model_copy(update={"start": Start(x=3.0, y=4.0, yaw=0.0), "events": (
        Event.model_validate({"at": 12.0, "walk_to": {"x": 1.0, "y": 4.0}}),
        Event.model_validate({"at": 12.5, "say": {"text": to_grace, "to": "Tom"}}))})
    seen: dict[float, tuple[float, float]] = {}
    with Simulation(base.model_copy(update={"people": (tom, grace)})) as sim:
        while sim.t < 22.0:
            sim.step()
            seen[round(sim.t, 1)] = (sim.world.people["Tom"].yaw, sim.world.people["Grace"].yaw)
    ends = 1.0 + speech_seconds(to_grace) + LOOK_AFTER_S, 12.0 + speech_seconds(to_robot)
    assert math.degrees(seen[2.0][0]) == pytest.approx(90.0)             # to Grace, north
    assert math.degrees(seen[round(ends[0] + 0.5, 1)][0]) == pytest.approx(180.0)   # back
    assert math.degrees(seen[13.0][0]) == pytest.approx(math.degrees(math.atan2(1.0, 1.3)))
    assert math.degrees(seen[round(ends[1] + LOOK_AFTER_S + 0.5, 1)][0]) == pytest.approx(180.0)
    assert math.degrees(seen[13.0][1]) == pytest.approx(180.0)   # walking west, not turned
