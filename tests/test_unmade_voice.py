"""No one is ignored: a voice the robot picks up but cannot make out still gets a response.
Free to move, the robot says it is coming over, goes to the speaker (find people towards
the voice), asks them to say it again there and answers; bound by a safety action it asks
them to come closer; a voice fainter than ``listening.unmade.min_snr_db`` (someone
talking elsewhere) it lets be. Runs use the real recogniser, its gate raised so that the
seated speaker's voice from across the room gives no words."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from app.responses import response_metrics
from app.run import build_run
from behaviours.config import load_behaviour_config
from behaviours.listening import not_made_out
from robot.percepts import HeardLine
from sim.scenario import Event, load_scenario

ROOT = Path(__file__).resolve().parents[1]
GATE_DB = 58.0   # speech quieter than this (after the beam) gives no words: Grace from 3 m


def grace_asks(duration: float):
    """worlds/living_room.yaml with Grace alone in her armchair, 3.3 m from the robot,
    asking the time at 3 s."""
    base = load_scenario(ROOT / "worlds" / "living_room.yaml")
    grace = next(q for q in base.people if q.name == "Grace")
    grace = grace.model_copy(update={"events": (Event.model_validate(
        {"at": 3.0, "say": "What time is it in London?"}),)})
    return base.model_copy(update={"people": (grace,), "duration": duration})


def run(scenario, out: Path, respond_snr_db: float | None = None) -> list[dict]:
    """Tick the whole run with the recogniser's level gate at :data:`GATE_DB` (and the
    response's at ``respond_snr_db``); its events and what was said (for scoring)."""
    household = build_run(scenario, out)
    recognizer, config = household.ctx.recognizer, household.ctx.config
    recognizer.cfg = recognizer.cfg.model_copy(update={"min_level_db": GATE_DB})
    if respond_snr_db is not None:
        unmade = config.listening.unmade.model_copy(update={"min_snr_db": respond_snr_db})
        listening = config.listening.model_copy(update={"unmade": unmade})
        household.ctx.config = config.model_copy(update={"listening": listening})
    with household.sim as sim:
        for _ in range(round(scenario.duration / scenario.step)):
            household.tree.tick()
        said = [{"kind": "line_said", **line} for line in sim.sound.said]
    return household.ctx.events.events + said


@pytest.fixture(scope="module")
def went_over(tmp_path_factory):
    return run(grace_asks(75.0), tmp_path_factory.mktemp("unmade"))


def test_a_voice_not_made_out_is_gone_to_asked_again_and_answered(went_over):
    events = went_over
    said = {e["line"]: e for e in events if e["kind"] == "line_said"}
    unmade = next(e for e in events if e["kind"] == "not_made_out")
    assert unmade["line"] == 1 and unmade["voiced"] and unmade["respond"]
    says = [e for e in events if e["kind"] == "say" and e.get("line") is not None]
    assert says[0]["line"] == 1 and says[0]["route"] == "coming_over"
    assert says[0]["t"] - said[1]["ended"] < 5.0          # a response within seconds
    went = next(e for e in events if e["kind"] == "action" and e["action"] == "find_people")
    assert went["reason"] == "asked" and went["t"] >= says[0]["t"]
    again = next(e for e in says if e["route"] == "say_again")
    assert again["line"] == 1 and again["behaviour"] == "Greet"
    repeat = next(s for s in said.values() if s["how"] == "repeat")
    assert repeat["level_db"] >= GATE_DB                 # said again from close by
    answer = next(e for e in says if e["line"] == repeat["line"])
    assert answer["route"] == "time" and "London" in answer["text"]
    metrics = response_metrics(events)
    assert (metrics["lines_responded"], metrics["lines_answered_at_all"],
            metrics["lines_ignored"], metrics["voices_approached"]) == (1, 1, 0, 1)


def test_a_voice_fainter_than_the_response_threshold_is_let_be(tmp_path):
    events = run(grace_asks(12.0), tmp_path, respond_snr_db=60.0)
    unmade = next(e for e in events if e["kind"] == "not_made_out")
    assert not unmade["respond"]
    assert not [e for e in events if e["kind"] == "say" and e.get("line") is not None]
    assert response_metrics(events)["lines_ignored"] == 1


def test_bound_to_its_spot_the_robot_asks_the_speaker_to_come_closer():
    cfg = load_behaviour_config().listening
    line = HeardLine(4, 10.0, "Grace", "", "robot", math.pi / 2, 0.0, unclear=True,
                     by_name=False)
    stay = not_made_out(cfg, line, can_move=False)
    assert (stay.text, stay.route, stay.action) == (cfg.come_closer, "say_again", None)
    go = not_made_out(cfg, line, can_move=True)
    assert go.route == "coming_over" and go.text == cfg.unmade.coming_over
    assert go.action.name == "find_people" and go.action.params == {"bearing": math.pi / 2,
                                                                   "line": 4}


def test_the_scoring_counts_responses_answers_and_the_ignored():
    def said(line, how="say", to="robot", person="Ann", text="hello there"):
        return {"kind": "line_said", "line": line, "person": person, "to": to, "how": how,
                "text": text, "ended": 10.0 * line}

    events = [said(1), said(2, "repeat"), said(3, text="what time is it"),
              said(4, to="Bob", text="tea?"), said(5, text="anyone?"),
              {"kind": "not_made_out", "line": 1}, {"kind": "heard", "line": 2},
              {"kind": "heard", "line": 3}, {"kind": "heard", "line": 4},
              {"kind": "say", "t": 12.0, "line": 1, "route": "coming_over"},
              {"kind": "say", "t": 40.0, "line": 2, "route": "chitchat"},
              {"kind": "say", "t": 35.0, "line": 3, "route": "say_again"}]
    m = response_metrics(events)
    assert (m["lines_responded"], m["lines_answered_at_all"], m["lines_ignored"]) == (2, 1, 1)
    assert (m["voices_detected"], m["voices_made_out"], m["voices_not_made_out"]) == (4, 3, 1)
    assert m["lines_responded_share"] == pytest.approx(2 / 3, abs=1e-4)
