"""The tablet during a household run: a line typed on the tablet is heard like any line (the
microphones, the inbox, Sense) and answered by the robot; 👍 enters as a scenario's feedback
event and is credited to the running action; the live view's snapshots follow the run; the
run folder keeps what `companion view` replays."""

from __future__ import annotations

import json
import threading
import time
from pathlib import Path

import httpx
import pytest

from app.run import RunOptions, run_scenario
from app.tablet.config import load_tablet_config
from app.tablet.replay import ReplayView
from app.tablet.run_link import RunTablet
from app.tablet.serve import TabletServer
from sim.scenario import load_scenario

ROOT = Path(__file__).resolve().parents[1]


def quiet_living_room(duration: float = 40.0):
    """worlds/living_room.yaml with nobody saying anything: only the tablet speaks."""
    base = load_scenario(ROOT / "worlds" / "living_room.yaml")
    people = tuple(q.model_copy(update={"events": ()}) for q in base.people)
    return base.model_copy(update={"people": people, "duration": duration})


@pytest.fixture(scope="module")
def played(tmp_path_factory):
    """A run served with --tablet; a client thread says a line and praises the robot."""
    out = tmp_path_factory.mktemp("tablet-run") / "run"
    config = load_tablet_config()
    tablet = RunTablet(config)
    got: dict = {}

    def person(base: str) -> None:
        deadline = time.monotonic() + 60
        while tablet.slot.seq == 0 and time.monotonic() < deadline:   # ticking yet?
            time.sleep(0.05)
        with httpx.Client(base_url=base, timeout=30) as client:
            got["say"] = client.post("/api/say", json={"text": "What time is it in London?",
                                                       "mode": "time"}).json()
            got["feedback"] = client.post("/api/feedback", json={"value": 1}).json()
            got["snapshot"] = client.get("/api/snapshot").json()

    with TabletServer(tablet, "127.0.0.1", 0) as server:
        client = threading.Thread(target=person, args=(f"http://127.0.0.1:{server.port}",))
        client.start()
        metrics = run_scenario(quiet_living_room(), out, RunOptions(tablet=tablet),
                               progress=False)
        client.join(timeout=60)
    return out, tablet, got, metrics


def events_of(out: Path) -> list[dict]:
    return [json.loads(line) for line in (out / "events.jsonl").read_text().splitlines()]


def test_a_tablet_line_is_heard_and_answered(played):
    out, tablet, got, _ = played
    events = events_of(out)
    typed = next(e for e in events if e["kind"] == "tablet_line")
    heard = next(e for e in events if e["kind"] == "heard")
    assert heard["line"] == typed["line"] and heard["person"] == "tablet user"
    said = next(e for e in events if e["kind"] == "say" and e.get("line") == heard["line"])
    assert said["route"] == "time" and "London" in said["text"]
    reply = next(r for r in tablet.replies.after(0) if r["input"] == said["in_reply_to"])
    assert reply["card"]["kind"] == "clock" and reply["card"]["city"] == "London"
    if not got["say"].get("pending"):
        assert got["say"]["seq"] == reply["seq"]
    assert tablet.replies.after(0)[-1]["t"] <= 40.0   # sim time of the reply
    assert typed["mode"] == "time" and tablet.run.ctx.dialogue.context.mode == "auto"


def test_the_tablet_feedback_is_credited_like_a_scenario_one(played):
    out, _, got, _ = played
    assert got["feedback"] == {"queued": True, "value": 1}
    events = events_of(out)
    pressed = next(e for e in events if e["kind"] == "tablet_feedback")
    sensed = next(e for e in events if e["kind"] == "feedback" and e["t"] >= pressed["t"])
    assert sensed["person"] == "tablet user" and sensed["value"] == 1
    credited = next(e for e in events if e["kind"] == "credited" and e["t"] >= pressed["t"])
    assert credited["reward"] == 1 and credited["person"] == "tablet user"


def test_the_live_view_follows_the_run(played):
    _, tablet, got, metrics = played
    snap = got["snapshot"]
    assert set(snap["drives"]) >= {"energy", "curiosity"} and len(snap["motivations"]) == 6
    assert all(lo <= hi for lo, hi in snap["ranges"].values())
    assert snap["action"] and "Sense" in snap["tree"] and snap["frame"]
    assert 0 < snap["t"] <= metrics["duration_s"]
    assert tablet.view.built >= 1


def test_the_run_folder_replays(played):
    out, _, _, metrics = played
    frames = sorted((out / "view").glob("frame-t*.jpg"))
    assert 40 / 5 - 1 <= len(frames) <= 40 / 5 + 1
    view = ReplayView(out, load_tablet_config())
    index = view.index()
    assert index["duration"] == pytest.approx(metrics["duration_s"], abs=1.0)
    assert index["frames"] == len(frames)
    early, late = view.snapshot_at(6.0), view.snapshot_at(index["duration"])
    assert early["t"] < late["t"] and late["action"]
    assert late["frame_src"].startswith("/api/file/") and late["frame_t"] > early["frame_t"]
    assert view.snapshot_at(0.0)["frame_src"] is None   # no frame before the first tick
    trees = [view.snapshot_at(f)["tree"] for f in (6.0, index["duration"])]
    assert all("Sense [✓]" in tree for tree in trees) and len(view.trees) == len(frames)
    answered = next(e["t"] for e in events_of(out) if e["kind"] == "say" and e.get("line"))
    assert [d["route"] for d in view.snapshot_at(answered)["dialogue"]] == ["time"]
    assert view.snapshot_at(answered - 0.5)["dialogue"] == []
