"""The fast hearing path: audible lines reach the robot with their words and levels, no
voice synthesised or recognised; too faint ones do not; a run and a sweep can choose it."""

from __future__ import annotations

import json
from pathlib import Path

from test_answering import living_room

from app.run import RunOptions, build_run, run_scenario
from app.sweep.spec import load_sweep
from robot.percepts import SayEvent, Sound
from sim.simulation import Simulation


def recording(hearing: str, where: tuple[float, float], noise_db: float | None = None
              ) -> tuple[Sound | None, bool]:
    """What the robot records of Tom saying a line from ``where`` (the living room's steady
    background at ``noise_db`` when given), and whether the audibility rule passes it."""
    scenario = living_room([])
    tom = scenario.people[0]
    start = tom.start.model_copy(update={"x": where[0], "y": where[1]})
    update: dict = {"people": (tom.model_copy(update={"start": start}),)}
    if noise_db is not None:
        room = scenario.rooms[0]
        noise = room.noise.model_copy(update={"level_db": noise_db})
        update["rooms"] = (room.model_copy(update={"noise": noise}),)
    scenario = scenario.model_copy(update=update)
    with Simulation(scenario, hearing=hearing) as sim:  # type: ignore[arg-type]
        here = sim.robot.base.pose()[:2]
        acoustics = sim.sound.acoustics
        audible = (acoustics.speech_db(where, here) >= acoustics.background_db(here)
                   - sim.robot.cfg.microphones.audible_below_noise_db)
        return sim.sound.record(SayEvent(1.0, "Tom", "what time is it in london")), audible


def test_a_near_line_comes_with_its_words_and_no_audio():
    sound, audible = recording("fast", (5.4, 2.6))
    assert audible and sound is not None and sound.words == "what time is it in london"
    assert sound.audio.size == 0 and sound.snr_db is not None and sound.snr_db > 10.0
    assert sound.bearing is not None   # the stand-in localiser places it: no array to steer
    heard, _ = recording("audio", (5.4, 2.6))
    assert heard is not None and heard.words is None and heard.audio.size > 0


def test_a_line_drowned_by_the_room_is_not_heard_on_either_path():
    for hearing in ("fast", "audio"):
        sound, audible = recording(hearing, (0.6, 0.6), noise_db=85.0)
        assert not audible and sound is None


def test_a_fast_run_answers_what_it_hears(tmp_path):
    scenario = living_room([(3.0, "What time is it in London?")], duration=15.0)
    metrics = run_scenario(scenario, tmp_path / "run", RunOptions(hearing="fast"),
                           progress=False)
    assert metrics["hearing"] == "fast" and metrics["lines_answered"] == 1
    events = [json.loads(line) for line in
              (tmp_path / "run" / "events.jsonl").read_text().splitlines()]
    heard = [e for e in events if e["kind"] == "heard"]
    assert heard and heard[0]["text"] == "what time is it in london"
    assert not (tmp_path / "run" / "audio").exists()


def test_a_sweep_can_hear_fast_without_changing_the_keys_of_audio_runs(tmp_path):
    world = Path(__file__).resolve().parents[1] / "worlds" / "living_room.yaml"
    spec = tmp_path / "sweep.yaml"
    spec.write_text(f"worlds: [{world}]\nseeds: [0]\nduration: 5\n")
    _, (audio,) = load_sweep(spec)
    spec.write_text(f"worlds: [{world}]\nseeds: [0]\nduration: 5\nhearing: fast\n")
    _, (fast,) = load_sweep(spec)
    assert audio.hearing == "audio" and fast.hearing == "fast"
    assert fast.key != audio.key and fast.option() == "hearing=fast"
    assert audio.option() == "default"


def test_build_run_passes_the_hearing_to_the_simulation(tmp_path):
    household = build_run(living_room([], duration=1.0), tmp_path / "b",
                          RunOptions(hearing="fast"))
    with household.sim as sim:
        assert sim.sound.hearing == "fast"


def test_sense_reports_each_voice_it_picks_up_with_its_bearing(tmp_path):
    import py_trees

    household = build_run(living_room([(2.0, "What time is it?")], duration=6.0), tmp_path,
                          RunOptions(hearing="fast"))
    voices = []
    with household.sim:
        for _ in range(60):
            household.tree.tick()
            voices += py_trees.blackboard.Blackboard.storage["/voices"]
    assert [(v.line, v.person, v.made_out) for v in voices] == [(1, "Tom", True)]
    assert abs(voices[0].bearing) < 0.5   # Tom stands due east (+x), the stand-in 10 deg off
