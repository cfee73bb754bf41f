"""The body skills (rest, stand_by, sing_dance) in the living room, the dance routines file
and speech audio."""

import wave
from collections.abc import Iterator
from pathlib import Path

import py_trees
import pybullet as p
import pytest
from py_trees.common import Status

from app.harness import run_skill
from app.wiring import make_context
from behaviours.blackboard import seed
from behaviours.context import Context
from behaviours.skills import rest, sing_dance, stand_by
from behaviours.skills.sing_dance import Dance
from core.config_files import ConfigError
from core.events import EventLog
from robot.dances import load_dances
from robot.speaker import Speaker
from robot.voices import Voice
from sim.robot import Robot
from sim.scenario import load_scenario
from sim.simulation import Simulation

WORLD = Path(__file__).resolve().parents[1] / "worlds" / "living_room.yaml"
SKILLS = {"rest": rest, "stand_by": stand_by, "sing_dance": sing_dance}
ARMS = ("LShoulderPitch", "LShoulderRoll", "LElbowRoll", "RShoulderPitch", "RShoulderRoll",
        "RElbowRoll")


class Watch(py_trees.behaviour.Behaviour):
    """Records the robot's posture, resting flag, posture-reached flag and joints per tick."""

    def __init__(self, robot: Robot) -> None:
        super().__init__("Watch")
        self.robot = robot
        self.seen: list[tuple] = []

    def update(self) -> Status:
        j = self.robot.joints
        self.seen.append((j.posture, j.resting, j.posture_reached(), j.positions()))
        return Status.RUNNING


def watched(skill: py_trees.behaviour.Behaviour, watch: Watch) -> py_trees.behaviour.Behaviour:
    """``skill`` with ``watch`` ticking beside it; the status is the skill's."""
    policy = py_trees.common.ParallelPolicy.SuccessOnSelected(children=[skill])
    return py_trees.composites.Parallel("Watched", policy=policy, children=[skill, watch])


def living_room_context(robot_config: Path | None = None) -> tuple[Simulation, Context]:
    sim = Simulation(load_scenario(WORLD), robot_config=robot_config)
    ctx = make_context(sim)
    ctx.camera_rate = 0.05   # these skills do not look; rendering dominates the run time
    return sim, ctx


@pytest.fixture
def living_room() -> Iterator[tuple[Simulation, Context]]:
    sim, ctx = living_room_context()
    yield sim, ctx
    sim.close()


def assert_standing(robot: Robot) -> None:
    stand = robot.cfg.postures["Stand"]
    assert robot.joints.posture == "Stand"
    targets = robot.joints.targets()
    assert all(abs(targets[j] - a) < 1e-6 for j, a in stand.items())


def test_rest_crouches_cools_faster_and_stands_up(tmp_path):
    hot = tmp_path / "hot_robot.yaml"
    hot.write_text("thermal: {initial_c: 55.0}\n")
    sim, ctx = living_room_context(hot)
    watch = Watch(ctx.robot)
    status, used = run_skill(sim, ctx, watched(rest.build(ctx), watch), "rest", 150)
    assert status == Status.SUCCESS
    assert 100 <= used < 120                       # Table 4.2: 100 steps of resting
    assert any(name == "Crouch" and resting and reached for name, resting, reached, _ in watch.seen)
    assert ctx.events.of_kind("say")[0]["text"] == "I need to take a rest"
    assert_standing(ctx.robot)
    assert ctx.robot.joints.posture_reached()
    rested = ctx.robot.thermal.temperature
    sim.close()

    standing = Simulation(load_scenario(WORLD), robot_config=hot)
    for _ in range(round(used / standing.dt)):
        standing.step()
    assert rested < standing.robot.thermal.temperature - 10.0
    standing.close()


def test_stand_by_sways_the_head_and_recentres(living_room):
    sim, ctx = living_room
    watch = Watch(ctx.robot)
    status, used = run_skill(sim, ctx, watched(stand_by.build(ctx), watch), "stand_by", 30)
    assert status == Status.SUCCESS
    assert 12 <= used < 15                         # Table 4.2: 12 steps of stand-by
    yaws = [q["HeadYaw"] for *_, q in watch.seen]
    assert max(yaws) > 0.2
    assert_standing(ctx.robot)
    assert ctx.robot.joints.posture_reached()
    assert abs(ctx.robot.joints.positions()["HeadYaw"]) < 0.03


def test_sing_dance_moves_the_arms_and_sings(living_room):
    sim, ctx = living_room
    watch = Watch(ctx.robot)
    status, used = run_skill(sim, ctx, watched(sing_dance.build(ctx), watch), "sing_dance",
                             60)
    assert status == Status.SUCCESS
    assert 30 <= used < 35
    start = watch.seen[0][3]
    moved = max(abs(q[j] - start[j]) for *_, q in watch.seen for j in ARMS)
    assert moved > 0.3
    book = load_dances(ctx.config.sing_dance.resolved_routines(), ctx.robot.joints.limits())
    routine = book.routines[0]
    assert ctx.events.of_kind("dance")[0]["title"] == routine.title
    sung = [e for e in ctx.events.of_kind("say") if e.get("song") == routine.title]
    assert [e["text"] for e in sung[:len(routine.lyrics)]] == [x.text for x in routine.lyrics]
    assert_standing(ctx.robot)
    assert ctx.robot.joints.posture_reached()


def test_dance_rotates_through_the_routines(living_room):
    sim, ctx = living_room
    seed(ctx, sim.scenario.robot.initial_drives())
    book = load_dances(ctx.config.sing_dance.resolved_routines(), ctx.robot.joints.limits())
    dance = Dance(ctx, speed=0.5)
    dance.setup()
    titles = []
    for _ in range(len(book.routines) + 1):
        dance.tick_once()
        titles.append(dance.routine.title)
        dance.stop(Status.INVALID)
    assert titles == [r.title for r in book.routines] + [book.routines[0].title]


@pytest.mark.parametrize("action", sorted(SKILLS))
def test_interrupted_skill_leaves_the_robot_commanded_to_stand(living_room, action):
    sim, ctx = living_room
    skill = SKILLS[action].build(ctx)
    status, _ = run_skill(sim, ctx, skill, action, 7.0)   # stopped with INVALID mid-run
    assert status == Status.RUNNING and skill.status == Status.INVALID
    assert_standing(ctx.robot)
    for _ in range(60):
        sim.step()
    assert ctx.robot.joints.posture_reached()


@pytest.fixture(scope="module")
def limits() -> Iterator[dict[str, tuple[float, float]]]:
    cid = p.connect(p.DIRECT)
    yield Robot(cid).joints.limits()
    p.disconnect(cid)


def test_packaged_routines_are_valid_and_song_length(limits):
    book = load_dances(Path(__file__).resolve().parents[1] / "config/dances.yaml", limits)
    assert len(book.routines) >= 3
    assert len({r.title for r in book.routines}) == len(book.routines)
    assert all(25 <= r.length_s <= 35 for r in book.routines)


ROUTINE = """
routines:
  - title: Test
    length_s: 10
    lyrics: [{at: 0, text: "la la la"}, {at: 3, text: "la la"}]
    keyframes: [{at: 0, joints: {%s}}]
"""


@pytest.mark.parametrize(("joints", "expected"), [
    ("LElbowRol: -1.0", "routines[0].keyframes[0].joints.LElbowRol: unknown key"),
    ("HipRoll: 0.9", "routines[0].keyframes[0].joints.HipRoll: 0.9 rad is outside"),
    ("", "routines[0].keyframes[0]: Value error, a keyframe needs at least one joint"),
])
def test_bad_routines_file_names_the_key(tmp_path, limits, joints, expected):
    path = tmp_path / "dances.yaml"
    path.write_text(ROUTINE % joints)
    with pytest.raises(ConfigError, match=r"invalid configuration") as err:
        load_dances(path, limits)
    assert expected in str(err.value)


def test_overlapping_lyrics_are_refused(tmp_path, limits):
    path = tmp_path / "dances.yaml"
    path.write_text((ROUTINE % "HeadYaw: 0.2").replace("{at: 3,", "{at: 0.5,"))
    with pytest.raises(ConfigError, match=r"routines\[0\]: Value error, lyrics\[0\] takes"):
        load_dances(path, limits)


def test_speaker_speaks_into_wav_files_in_its_voice(tmp_path):
    events = EventLog(None, lambda: 0.0)
    speaker = Speaker(events, audio_dir=tmp_path / "speech", voice=Voice(pitch=58))
    assert speaker.say("I need to take a rest") == pytest.approx(2.4)
    speaker.say("Hello!")
    assert [e["audio"] for e in events.of_kind("say")] == ["0001.wav", "0002.wav"]
    with wave.open(str(tmp_path / "speech" / "0001.wav")) as w:
        assert (w.getnchannels(), w.getsampwidth(), w.getframerate()) == (1, 2, 22050)
        seconds = w.getnframes() / w.getframerate()
    assert 1.0 < seconds < 3.5        # five words at 150 a minute, with the voice's pauses


def test_speaker_without_audio_only_logs(tmp_path):
    events = EventLog(None, lambda: 0.0)
    Speaker(events).say("Hello there")
    assert "audio" not in events.of_kind("say")[0]
