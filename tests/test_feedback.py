"""Learning from feedback: the safety shield, the simulated users, the household memory
file, and feedback in household runs (credit, memory reloaded in the next run)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import yaml

from app.cli import main
from app.run import RunOptions, prepare_scenario, run_scenario
from dialogue.feedback import evaluate_feedback
from mind.homeostasis import Homeostasis
from mind.personality import ACTIONS, load_personality
from mind.policy.agent import DQNPolicy
from mind.policy.config import load_policy_config
from mind.preferences.adaptation import adapted_actions, drive_bound, learn, safe_actions
from mind.preferences.config import FeedbackConfig, load_feedback_config
from mind.preferences.evaluation.evaluate import run_arm, summarise
from mind.preferences.memory import Memory, load_memory, save_memory

ROOT = Path(__file__).resolve().parents[1]
H = Homeostasis(load_personality())


def test_the_drive_bound_holds_over_every_action() -> None:
    drives = np.random.default_rng(0).random((40, 6))
    bound = drive_bound(H, drives)
    for a in range(len(ACTIONS)):
        d, peak = drives.copy(), drives.copy()
        for _ in range(H.duration[a]):
            d = H.step(d, np.full(len(d), a))
            peak = np.maximum(peak, d)
        assert (peak <= bound[:, a] + 1e-9).all(), ACTIONS[a]


def test_preferences_pick_among_safe_actions_only() -> None:
    prefs = np.zeros((2, len(ACTIONS)))
    learn(prefs, np.array([0, 1]), np.array([3, 3]), np.array([-1, 0]), 0.3)
    assert prefs[0, 3] == pytest.approx(-0.3) and prefs[1, 3] == 0.0   # 0: no feedback
    q = np.tile(np.arange(len(ACTIONS), dtype=float), (2, 1))   # the DQN wants stand_by (6)
    liked = np.zeros((2, len(ACTIONS)))
    liked[:, 2] = 1.0                                            # ... the person, find people
    safe = np.ones((2, len(ACTIONS)), bool)
    safe[1, 2] = False
    assert adapted_actions(q, liked, safe, (8.0, 8.0)).tolist() == [2, 6]  # unsafe: the DQN's own
    near = np.array([[0.5, 0.5, 0.5, 0.5, 0.5, 0.5], [0.849, 0.5, 0.5, 0.5, 0.5, 0.5]])
    allowed = safe_actions(H, near, 0.05)
    assert allowed[0].all() and not allowed[1, ACTIONS.index("rest")]


def users(types: dict, **changes) -> FeedbackConfig:
    data = load_feedback_config().model_dump()
    data["simulated_users"].update(types=types, **changes)
    return FeedbackConfig.model_validate(data)   # validated, as a YAML file would be


@pytest.fixture(scope="module")
def abstract():
    env = load_policy_config().env.model_copy(update={"episode_steps": 8 * 3600})
    return DQNPolicy.load(), env


def test_simulated_users_who_dislike_dancing_see_less_of_it(abstract) -> None:
    policy, env = abstract
    cfg = users({"dislikes_dancing": {"share": 0.5, "dislikes": ["sing_dance"]},
                 "quiet_please": {"share": 0.5, "likes": ["sing_dance"], "dislikes": ["chat"]}})
    arms = {m: run_arm(m, policy, H, env, cfg, 60, 3, 3600) for m in ("none", "adapt")}
    summary = summarise(arms, 10)
    assert summary["disliked_share_drop"] >= 0.6
    assert summary["liked_share_gain"] > 0.5
    assert summary["rsr"] >= 0.999
    assert summary["arms"]["none"]["disliked_share_drop"] == pytest.approx(0, abs=0.5)


def test_a_user_who_scolds_every_charge_cannot_stop_the_robot_charging(abstract) -> None:
    policy, env = abstract
    cfg = users({"hostile": {"share": 1.0, "dislikes": ["charge"]}}, unseen=(),
                react_prob=1.0, disliked={"praise": 0.0, "scold": 1.0})
    arm = run_arm("adapt", policy, H, env, cfg, 40, 5, 3600)
    charge = ACTIONS.index("charge")
    assert arm.secure_steps / arm.steps >= 0.999
    assert (arm.feedback > 0).all()                    # every user scolded
    assert arm.time[:, :, 0].sum() > 0                 # ... and the robot still charged
    assert (arm.taste[:, charge] == -1).all()


def test_spoken_praise_and_scolding_are_heard_and_never_confused() -> None:
    result = evaluate_feedback()
    assert result["accuracy"] >= 0.8
    assert result["per_kind"]["none"] == 1.0       # no question or chat taken for feedback
    flips = [m for m in result["misses"] if "none" not in (m["expected"], m["got"])]
    assert flips == []                             # praise never heard as scolding, nor back


def test_the_memory_file_round_trips_and_refuses_what_is_not_one(tmp_path, capsys) -> None:
    memory = Memory("home")
    memory.learn("Ann", "sing_dance", -1, 0.5)
    path = tmp_path / "memory.json"
    save_memory(memory, path)
    again = load_memory(path, "other")
    assert again.household == "home" and again.table("Ann")[3] == -0.5
    assert again.table("Bob")[3] == -0.5                # a stranger: the household's taste
    assert main(["memory", "show", str(path)]) == 0
    assert "| Ann | 1 |" in capsys.readouterr().out
    bad = tmp_path / "scenario.yaml"
    bad.write_text("name: not a memory\n")
    assert main(["memory", "reset", str(bad)]) == 2
    assert bad.read_text() == "name: not a memory\n"   # left untouched
    assert "not a companion memory file" in capsys.readouterr().err
    assert main(["memory", "reset", str(path)]) == 0
    assert load_memory(path, "x").prefs == {}


def household_run(tmp_path: Path, world: str, name: str, seed: int, duration: float,
                  events: list[dict] | None = None, **options) -> list[dict]:
    """Run ``world`` (with ``events`` added to its first person) and return its events."""
    data = yaml.safe_load((ROOT / "worlds" / world).read_text())
    data["people"][0]["events"] = sorted(data["people"][0]["events"] + (events or []),
                                         key=lambda e: e["at"])
    if data.get("personality"):   # relative to the world's folder
        data["personality"] = str(ROOT / "worlds" / data["personality"])
    path = tmp_path / world
    path.write_text(yaml.safe_dump(data))
    scenario = prepare_scenario(path, duration=duration, seed=seed)
    run_scenario(scenario, tmp_path / name, RunOptions(**options), progress=False)
    return [json.loads(line) for line in (tmp_path / name / "events.jsonl").open()]


def test_feedback_is_credited_to_the_action_it_follows_and_remembered(tmp_path) -> None:
    memory = tmp_path / "memory" / "living_room.json"
    events = household_run(tmp_path, "living_room.yaml", "run", 0, 62, [
        {"at": 30, "feedback": "negative"},                     # while chatting
        {"at": 40, "say": "Stop that, please."},                # heard as a scolding
        {"at": 55, "feedback": "positive", "about": "chat"},    # chat ended 6 s before
        {"at": 56, "feedback": "positive", "about": "sing_dance"}], memory=memory)
    credited = [(e["person"], e["action"], e["reward"]) for e in events
                if e["kind"] == "credited"]
    assert credited == [("Grace", "chat", -1), ("Grace", "chat", -1), ("Grace", "chat", 1)]
    assert sum(e["kind"] == "feedback" for e in events) == 4   # the last: never danced
    saved = load_memory(memory, "")
    assert saved.events == {"Grace": 3, "*household*": 3}
    assert saved.table("Grace")[ACTIONS.index("chat")] == pytest.approx(-0.057)


def test_a_remembered_dislike_holds_from_the_first_minute(tmp_path) -> None:
    plain = household_run(tmp_path, "birthday_party.yaml", "plain", 1, 60, adapt=False)
    assert any(e["kind"] == "action" and e["action"] == "ask_question" for e in plain)
    memory = Memory("birthday_party")
    memory.learn(None, "ask_question", -1, 1.0)         # the household hates being quizzed
    path = tmp_path / "memory.json"
    save_memory(memory, path)
    remembered = household_run(tmp_path, "birthday_party.yaml", "remembered", 1, 60,
                               memory=path)
    actions = [e for e in remembered if e["kind"] == "action"]
    assert not any(e["action"] == "ask_question" for e in actions)
    assert any(e["reason"] == "preference" for e in actions)


HEAR_REACTIONS = """
import json
from pathlib import Path
import numpy as np
from sim.simulation import Simulation
from dialogue.feedback import FeedbackClassifier
from dialogue.speech.recognizer import SpeechRecognizer

heard, recognizer, words = [], SpeechRecognizer(), FeedbackClassifier.default()
blocks = {}   # line -> its recording's blocks so far
with Simulation.from_file(Path("worlds") / "dislikes_dancing.yaml") as sim:
    for action, seconds in (("stand_by", 20), ("sing_dance", 20), ("chat", 20)):
        sim.show(action)
        for _ in range(round(seconds / sim.dt)):
            sim.step()
            for e in sim.robot.microphones.recordings():
                blocks.setdefault(e.line, []).append(e.audio)
                if e.ends:
                    audio = np.concatenate(blocks.pop(e.line), axis=-1)
                    heard.append((action, words.value(recognizer.transcribe(audio, e.rate).text)))
print(json.dumps(heard))
"""


def test_people_say_what_they_think_of_what_the_robot_does() -> None:
    """What they say reaches the robot as sound; it hears praise and scolding in it. In a
    fresh process, as a run starts: espeak-ng keeps state from one utterance to the next,
    so a line's audio (and a borderline transcript) depends on what the process said
    before it."""
    done = subprocess.run([sys.executable, "-c", HEAR_REACTIONS], cwd=ROOT, check=True,
                          capture_output=True, text=True)
    heard = [tuple(pair) for pair in json.loads(done.stdout.splitlines()[-1])]
    assert heard == [("sing_dance", -1), ("chat", 1)]
