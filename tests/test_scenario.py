"""Scenario YAML: the shipped worlds load, broken files fail naming the key and the reason."""

from pathlib import Path

import pytest
import yaml

from core.config_files import ConfigError
from mind.personality import DRIVES
from sim.scenario import load_scenario

WORLDS = Path(__file__).resolve().parents[1] / "worlds"
NAMES = ("living_room", "nursing_home", "birthday_party", "low_battery_night")


def minimal() -> dict:
    """A small valid scenario as plain data; tests break one thing at a time."""
    return {
        "name": "test", "duration": 100, "step": 0.1,
        "rooms": [{"name": "room", "x": [0, 5], "y": [0, 4],
                   "doors": [{"name": "door", "wall": "south", "offset": 1.0}]}],
        "furniture": [{"name": "table", "type": "table", "x": 2.5, "y": 2.0}],
        "objects": [{"type": "mug", "on_top_of": "table"}],
        "dock": {"x": 4.5, "y": 0.5, "yaw": -90},
        "robot": {"start": {"x": 1.0, "y": 1.0}, "battery": 0.5},
        "people": [
            {"name": "Ann", "start": {"x": 1.0, "y": 3.0},
             "events": [{"at": 5, "say": "How are you today?"},
                        {"at": 10, "walk_to": {"x": 3.5, "y": 3.0}}]},
            {"name": "Ben", "events": [{"at": 20, "enter": {"door": "door"}},
                                       {"at": 40, "leave": True}]},
        ],
    }


def write(tmp_path: Path, data: dict, name: str = "scenario.yaml") -> Path:
    path = tmp_path / name
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    return path


def problems(tmp_path: Path, data: dict) -> list[str]:
    with pytest.raises(ConfigError) as exc:
        load_scenario(write(tmp_path, data))
    return exc.value.problems


@pytest.mark.parametrize("name", NAMES)
def test_shipped_worlds_load(name):
    s = load_scenario(WORLDS / f"{name}.yaml")
    assert s.name == name and s.people and s.furniture and s.objects
    assert set(s.robot.drives.model_dump()) == set(DRIVES)
    assert s.personality is None or s.personality.is_absolute()


def test_world_contents_match_their_story():
    party = load_scenario(WORLDS / "birthday_party.yaml")
    cake = next(o for o in party.objects if o.type == "cake")
    assert cake.candles > 0 and cake.on_top_of == "cake_table"
    home = load_scenario(WORLDS / "nursing_home.yaml")
    assert sum(p.start is not None and p.start.pose == "sitting" for p in home.people) >= 2
    night = load_scenario(WORLDS / "low_battery_night.yaml")
    assert night.robot.battery < 0.2 and night.lighting.ambient < 0.3
    assert len(night.people) <= 2
    assert home.personality is not None and home.personality.name == "sociable.yaml"


def test_minimal_scenario_and_defaults(tmp_path):
    s = load_scenario(write(tmp_path, minimal()))
    say = s.people[0].events[0]
    assert say.kind == "say" and say.say.to == "robot"
    assert s.robot.drives.energy == 0.0 and s.personality is None
    assert s.people[1].start is None


def _set(data: dict, path: str, value: object) -> dict:
    """Set ``value`` at a dotted path like ``people.0.events.0.at``."""
    *parents, last = path.split(".")
    node = data
    for key in parents:
        node = node[int(key)] if isinstance(node, list) else node[key]
    if isinstance(node, list):
        node[int(last)] = value
    else:
        node[last] = value
    return data


BROKEN = [
    ("people.0.events.0.at", -1,
     "people[0].events[0].at: Input should be greater than or equal to 0"),
    ("climate", "sunny", "climate: unknown key"),
    ("weather", {"cities": {"Oslo": {"today": {"condition": "snow", "temp_c": -3,
                                                "humidity": 120}}}},
     "weather.cities.Oslo.today.humidity: Input should be less than or equal to 100"),
    ("people.0.body", {"shirt": "blue"},
     "people[0].body.shirt: Value error, expected a colour like '#3a7bd5', got 'blue'"),
    ("people.0.events.0", {"at": 5, "say": {"text": "Hi Bob!", "to": "Bob"}},
     "people[0].events[0].say.to: no other person named 'Bob'"),
    ("people.0.events.1", {"at": 10, "walk_to": {"person": "Zoe"}},
     "people[0].events[1].walk_to.person: no other person named 'Zoe'"),
    ("people.1.events.1.at", 150,
     "people[1].events[1].at: 150 s is not before the end of the scenario (duration 100 s)"),
    ("people.0.events.1.walk_to", {"x": 20, "y": 1},
     "people[0].events[1].walk_to: (20, 1) is not inside a room"),
    ("people.0.events.0", {"at": 5, "say": "Hi", "emotion": "happy"},
     "people[0].events[0]: Value error, an event needs exactly one of"),
    ("people.0.events.0", {"at": 5, "emotion": "angry"},
     "people[0].events[0].emotion: Input should be 'happy', 'sad' or 'neutral'"),
    ("people.0.gives_way", "maybe", "people[0].gives_way: Input should be a valid boolean"),
    ("people.0.events.0", {"at": 5, "enter": {"door": "door"}},
     "people[0].events[0].enter: Ann is already in the world at 5 s"),
    ("people.1.events.0", {"at": 20, "enter": {"door": "garage"}},
     "people[1].events[0].enter.door: no door named 'garage'"),
    ("people.1.events.0.at", 45, "people[1].events[1].at: events must be in time order"),
    ("people.1.name", "Ann", "people: name 'Ann' is used more than once"),
    ("robot.drives", {"energy": 1.5},
     "robot.drives.energy: Input should be less than or equal to 1"),
    ("robot.drives", {"hunger": 0.5}, "robot.drives.hunger: unknown key"),
    ("robot.battery", -0.1, "robot.battery: Input should be greater than or equal to 0"),
    ("objects.0.on_top_of", "desk", "objects[0].on_top_of: no furniture named 'desk'"),
    ("objects.0.candles", 3, "objects[0].candles: only a cake has candles"),
    ("objects.0", {"type": "mug", "on_top_of": "table", "x": 0.5, "y": 0.5},
     "objects[0]: (0.5, 0.5) is not on top of 'table'"),
    ("people.1.name", "robot", "people: 'robot' is reserved"),
    ("dock", {"x": 9, "y": 1}, "dock: (9, 1) is outside the rooms"),
    ("rooms.0.doors.0.offset", 4.9,
     "rooms[0]: Value error, door 'door' does not fit in the south wall"),
    ("furniture.0.type", "piano", "furniture[0].type: Input should be 'table'"),
    ("camera_rate", 50, "camera_rate: Input should be less than or equal to 30"),
    ("time_of_day", "25:00", "time_of_day: String should match pattern"),
    ("duration", float("inf"), "duration: Input should be a finite number"),
    ("duration", float("nan"), "duration: Input should be a finite number"),
    ("duration", 1e300, "duration: Input should be less than or equal to 604800"),
    ("seed", 10**23, "seed: Input should be less than or equal to 4294967295"),
    ("robot.start", {"x": 2.5, "y": 2.0}, "robot.start: (2.5, 2) is inside the table 'table'"),
    ("robot.start", {"x": 3.0, "y": 0.1}, "robot.start: (3, 0.1) is inside the south wall of"),
    ("people.0.start", {"x": 2.5, "y": 4.0},
     "people[0].start: (2.5, 4) is inside the north wall of 'room'"),
    ("people.0.start", {"x": 2.3, "y": 1.8, "pose": "sitting"},
     "people[0].start: (2.3, 1.8) is inside the table 'table'"),
    ("dock", {"x": 2.9, "y": 2.3}, "dock: (2.9, 2.3) is inside the table 'table'"),
]


@pytest.mark.parametrize(("path", "value", "expected"), BROKEN,
                         ids=[b[2].split(":")[0] + "-" + str(i) for i, b in enumerate(BROKEN)])
def test_broken_scenarios_name_the_key(tmp_path, path, value, expected):
    found = problems(tmp_path, _set(minimal(), path, value))
    assert any(p.startswith(expected) for p in found), found


def test_a_door_opens_the_wall_and_seats_hold_seated_people(tmp_path):
    data = minimal()
    data["robot"]["start"] = {"x": 1.0, "y": 0.05}   # in the door gap of the south wall
    data["furniture"].append({"name": "sofa", "type": "sofa", "x": 0.6, "y": 2.5})
    data["people"][0]["start"] = {"x": 0.6, "y": 2.5, "pose": "sitting"}
    assert load_scenario(write(tmp_path, data)).robot.start.y == 0.05
    data["people"][0]["start"]["pose"] = "standing"
    assert problems(tmp_path, data) == ["people[0].start: (0.6, 2.5) is inside the sofa 'sofa'"]


@pytest.mark.parametrize(("text", "expected"), [
    ("name: a\nname: b\n", "not valid YAML: line 2, column 1: found the key 'name' twice"),
    ("rooms: [\n", "not valid YAML: line 2, column 1"),
    ("- 1\n", "top level must be a mapping"),
])
def test_bad_yaml_is_one_clear_problem(tmp_path, text, expected):
    path = tmp_path / "s.yaml"
    path.write_text(text)
    with pytest.raises(ConfigError) as exc:
        load_scenario(path)
    assert len(exc.value.problems) == 1 and exc.value.problems[0].startswith(expected)


def test_all_problems_are_reported_together(tmp_path):
    data = _set(minimal(), "people.0.events.0.at", 500)
    data = _set(data, "people.0.events.1.walk_to", {"x": 20, "y": 1})
    found = problems(tmp_path, data)
    assert len(found) >= 2


def test_missing_personality_file(tmp_path):
    found = problems(tmp_path, _set(minimal(), "personality", "personalities/nope.yaml"))
    assert found == [f"personality: file not found: {tmp_path / 'personalities' / 'nope.yaml'}"]


def test_personality_resolved_next_to_the_scenario(tmp_path):
    (tmp_path / "personalities").mkdir()
    (tmp_path / "personalities" / "calm.yaml").write_text("reward:\n  kappa: 2.0\n")
    s = load_scenario(write(tmp_path, _set(minimal(), "personality", "personalities/calm.yaml")))
    assert s.personality == tmp_path / "personalities" / "calm.yaml"


def test_bad_personality_value_is_reported_under_personality(tmp_path):
    (tmp_path / "bad.yaml").write_text("reward:\n  lambda: 0.5\n")
    found = problems(tmp_path, _set(minimal(), "personality", "bad.yaml"))
    assert found == ["personality: reward.lambda: Input should be less than 0"]


def test_yaml_is_loaded_safely(tmp_path):
    path = tmp_path / "evil.yaml"
    path.write_text("name: !!python/object/apply:os.system ['echo pwned']\nduration: 10\n")
    with pytest.raises(ConfigError) as exc:
        load_scenario(path)
    assert "not valid YAML" in exc.value.problems[0]


def test_yes_no_style_keys_do_not_sneak_in(tmp_path):
    """YAML 1.1 reads a bare ``on`` key as True; the schema rejects it instead of ignoring it."""
    path = tmp_path / "on.yaml"
    path.write_text(yaml.safe_dump(minimal()).replace("on_top_of:", "on:"))
    with pytest.raises(ConfigError):
        load_scenario(path)


def test_energy_drive_is_the_battery(tmp_path):
    data = minimal()
    data["robot"]["battery"] = 0.7
    assert load_scenario(write(tmp_path, data)).robot.initial_drives()["energy"] == \
        pytest.approx(0.3)
    data["robot"]["drives"] = {"energy": 0.6}
    found = problems(tmp_path, data)
    assert len(found) == 1 and "drives.energy" in found[0] and "battery" in found[0]
