"""Find people beyond the current view: where the robot searches next after a look around
(memory of where people were, rooms not searched lately, never the same empty room twice in
a row), walking through a door to a person in another room, greeting a person across a
table, and boxes that cannot be people."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from conftest import WEIGHTS
from py_trees.common import Status
from test_find_people import find

from app.wiring import make_context
from behaviours.skills.detour import Detour
from behaviours.skills.search import Search, remember
from sim.layout import Placement
from sim.scenario import Start, load_scenario
from sim.simulation import Simulation

ROOT = Path(__file__).resolve().parents[1]


def nursing_home(robot: Placement, person: Start | None = None, personality: Path | None = None):
    """worlds/nursing_home.yaml with only Walter, still at ``person`` (or nobody)."""
    base = load_scenario(ROOT / "worlds" / "nursing_home.yaml")
    walter = next(q for q in base.people if q.name == "Walter")
    people = () if person is None else (walter.model_copy(update={"start": person,
                                                                  "events": ()}),)
    return base.model_copy(update={"people": people, "personality": personality,
                                   "robot": base.robot.model_copy(update={"start": robot})})


@pytest.fixture(scope="module")
def search():
    with Simulation(nursing_home(Placement(x=6.5, y=2.0, yaw=90))) as sim:
        ctx = make_context(sim, None, None)
        yield Search(ctx, Detour(ctx))


def test_sightings_replace_the_same_place_and_keep_the_latest():
    seen = remember([], (1.0, 1.0), 5.0, keep=2)
    seen = remember(seen, (1.3, 1.2), 9.0, keep=2)        # the same person, moved a little
    assert seen == [(1.3, 1.2, 9.0)]
    seen = remember(remember(seen, (5.0, 5.0), 10.0, 2), (8.0, 2.0), 11.0, 2)
    assert seen == [(5.0, 5.0, 10.0), (8.0, 2.0, 11.0)]


def test_a_full_turn_is_a_look_around(search):
    search.turned = 0.0
    assert not search.turn(0.8, 7.0)
    assert search.turn(-0.8, 1.0)        # either way round counts


def test_where_people_were_seen_comes_first(search):
    choice = search.go_on((8.0, 1.0), 100.0, [(2.6, 5.2, 20.0), (4.5, 4.6, 60.0)], {}, [])
    assert choice == ("last seen", (4.5, 4.6))          # the most recent sighting
    old = search.go_on((8.0, 1.0), 2000.0, [(4.5, 4.6, 60.0)], {}, [])
    assert old[0] == "room"                              # forgotten after sighting_memory_s
    given_up = search.go_on((8.0, 1.0), 100.0, [(4.5, 4.6, 60.0)], {}, [(4.6, 4.4)])
    assert given_up[0] == "room"                         # a spot it gave up on is skipped


def test_the_same_empty_room_is_not_searched_twice_in_a_row(search):
    # the robot has just looked round the corridor in vain: the lounge is next, though it
    # was searched in vain before; and the other way round
    assert search.go_on((2.0, -1.2), 50.0, [], {"lounge": 10.0, "corridor": 50.0}, []) == (
        "room", (5.0, 3.5))
    assert search.go_on((5.0, 3.5), 90.0, [], {"corridor": 50.0, "lounge": 90.0}, []) == (
        "room", (5.0, -1.25))


def test_a_house_of_one_room_is_searched_on_its_far_side(search):
    rooms = search.rooms
    search.rooms = {"lounge": rooms["lounge"]}
    try:
        why, goal = search.go_on((5.0, 3.5), 90.0, [], {"lounge": 90.0}, [])
    finally:
        search.rooms = rooms
    assert why == "elsewhere" and search.room_of(goal) == "lounge"
    assert math.dist(goal, (5.0, 3.5)) >= search.cfg.search.revisit_min_m


def test_a_box_inside_a_wall_is_no_person(search):
    assert search.on_wall((5.0, 0.02)) and search.on_wall((0.05, 3.0))
    assert not search.on_wall((5.0, 3.5)) and not search.on_wall((8.5, 0.0))   # the door


pytestmark = pytest.mark.skipif(not WEIGHTS, reason="no detector weights")


def test_a_person_in_another_room_is_found_through_the_door(detector, short_relief):
    # the robot stands at the corridor's far end: nobody in view all the way round, so it
    # walks into the lounge and finds Walter there
    person = Start(x=5.0, y=4.0, yaw=-90.0, pose="standing")
    scenario = nursing_home(Placement(x=1.5, y=-1.2, yaw=180.0), person, short_relief)
    status, events, (x, y, _), _ = find(scenario, detector, max_seconds=70.0)
    assert status == Status.SUCCESS
    walk = events.of_kind("search_on")[0]
    assert walk["why"] == "room" and walk["searched"] == "corridor"
    assert y > 0.0 and math.hypot(person.x - x, person.y - y) < 1.3


def test_a_person_across_a_table_is_greeted_from_there(detector, short_relief):
    # Harold sits at the dining table facing it; no spot 1 m in front of him is free, so
    # the robot goes round to the table's far side and greets him across it
    from perception.facing.config import DEFAULT_FACING_MODEL
    from perception.facing.model import FacingEstimator

    person = Start(x=1.3, y=1.8, yaw=0.0, pose="sitting")
    scenario = nursing_home(Placement(x=6.5, y=2.0, yaw=90.0), person, short_relief)
    status, events, (x, y, _), _ = find(scenario, detector, max_seconds=45.0,
                                         facing=FacingEstimator.load(DEFAULT_FACING_MODEL))
    assert status == Status.SUCCESS and events.of_kind("person_found")
    assert 1.2 < math.hypot(person.x - x, person.y - y) <= 1.75
    assert abs(math.degrees(math.atan2(y - person.y, x - person.x))) <= 45.0   # in his view
