"""The tablet's web app without a browser (starlette's TestClient): every conversation
button answers with a card drawn from local data, files are served by id only, and the
guard refuses what it must (token, Host, body size, bad input)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import py_trees
import pytest
from starlette.testclient import TestClient

from app.tablet.cards import FileRegistry
from app.tablet.chat_link import ChatTablet
from app.tablet.config import KINDS, load_tablet_config
from app.tablet.record import ViewFrames, frame_time
from app.tablet.run_link import RunTablet
from app.tablet.server import CSP, create_app
from core.config_files import ConfigError

ROOT = Path(__file__).resolve().parents[1]
CARD_OF = {"information": "knowledge", "weather": "weather", "time": "clock", "news": "news",
           "related_topics": "knowledge", "map": "image", "music": "song", "photo": "image"}


@pytest.fixture(scope="module")
def backend(tmp_path_factory):
    out = tmp_path_factory.mktemp("tablet")
    tablet = ChatTablet.from_scenario(ROOT / "worlds" / "living_room.yaml",
                                      load_tablet_config(), out)
    yield tablet
    tablet.close()


@pytest.fixture(scope="module")
def client(backend):
    return TestClient(create_app(backend), base_url="http://127.0.0.1")


def test_every_button_answers_with_its_card(client, backend):
    buttons = client.get("/api/config").json()["buttons"]
    assert [b["kind"] for b in buttons] == list(KINDS)
    for b in buttons:
        reply = client.post("/api/say", json={"text": b["line"], "mode": b["kind"]}).json()
        assert reply["route"] == b["kind"] and reply["text"]
        card = reply["card"]
        if b["kind"] == "chitchat":
            assert card is None
            continue
        assert card["kind"] == CARD_OF[b["kind"]], (b, card)
        if card["kind"] == "image":   # the map and the photo: served by id from the out folder
            image = client.get(card["src"])
            assert image.status_code == 200 and image.content[:4] == b"\x89PNG"
    seqs = [r["seq"] for r in client.get("/api/replies?after=0").json()]
    assert seqs == sorted(seqs) and len(seqs) == len(KINDS)


def test_cards_hold_the_local_data(client):
    def ask(text, mode="auto"):
        return client.post("/api/say", json={"text": text, "mode": mode}).json()["card"]

    clock = ask("What time is it in London?")
    assert clock["city"] == "London" and 0 <= clock["hour"] < 24
    assert clock["link"] == "https://time.is/London"     # shown as text, never loaded
    weather = ask("What's the weather tomorrow?")
    days = {d["day"]: d for d in weather["days"]}
    assert weather["city"] == "London" and days["tomorrow"]["current"]
    assert days["today"]["condition"] == "light drizzle"   # worlds/living_room.yaml's block
    news = ask("What's in the news?")
    assert news["items"] and news["items"][0]["current"]
    place = ask("Where is Paris on the map?", "map")
    assert place["kind"] == "place" and abs(place["lat"] - 48.85) < 0.1
    assert ask("Tell me about jazz")["title"].lower() == "jazz"
    assert ask("What is a snorgleplax?", "information") is None   # "I don't know": no card


def test_feedback_is_taken(client):
    assert client.post("/api/feedback", json={"value": -1}).json()["value"] == -1
    assert client.post("/api/feedback", json={"value": 2}).status_code == 400
    assert client.post("/api/feedback", json={"value": True}).status_code == 400


def test_pages_load_nothing_from_elsewhere(client):
    for path in ("/", "/mind", "/static/tablet.js", "/static/mind.js", "/static/cards.js",
                 "/static/style.css"):
        r = client.get(path)
        assert r.status_code == 200 and r.headers["content-security-policy"] == CSP
        text = r.text.replace("http://www.w3.org/2000/svg", "")   # a name, not an address
        assert "http://" not in text and "https://" not in text and "//cdn" not in text


def test_no_path_reaches_the_file_system(client, tmp_path):
    for path in ("/static/..%2f..%2fpyproject.toml", "/static/../../pyproject.toml",
                 "/api/file/..%2fdialogue.jsonl", "/api/file/f999", "/static/tablet.yaml"):
        assert client.get(path).status_code == 404, path
    outside = tmp_path / "secret.png"
    outside.write_bytes(b"\x89PNG")
    files = FileRegistry(tmp_path / "run")
    assert files.add(outside) is None and files.add(tmp_path / "run" / ".." / "secret.png") is None


def test_bad_requests_are_refused(client, backend):
    assert client.post("/api/say", json={"text": "hi", "mode": "nonsense"}).status_code == 400
    assert client.post("/api/say", json={"text": "  "}).status_code == 400
    assert client.post("/api/say", content=b"not json").status_code == 400
    assert client.post("/api/say", json=["a list"]).status_code == 400
    limit = backend.config.server.max_body_bytes
    big = {"text": "x" * limit, "mode": "auto"}
    assert client.post("/api/say", json=big).status_code == 413

    def chunks():
        yield b'{"text": "'
        for _ in range(limit // 100 + 1):
            yield b"y" * 100
        yield b'"}'
    assert client.post("/api/say", content=chunks()).status_code == 413   # no Content-Length
    assert client.get("/api/replies?after=-1").status_code == 400
    assert client.get("/", headers={"host": "attacker.example"}).status_code == 421


def test_any_other_host_needs_the_token(backend):
    app = create_app(backend, token="s3cret", loopback=False)
    client = TestClient(app, base_url="http://192.0.2.1")
    assert client.get("/").status_code == 401
    assert client.get("/api/config", headers={"x-tablet-token": "wrong"}).status_code == 401
    first = client.get("/?token=s3cret")
    assert first.status_code == 200 and "tablet_token=s3cret" in first.headers["set-cookie"]
    assert client.get("/api/config").status_code == 200     # the cookie carries it now
    assert TestClient(app, base_url="http://192.0.2.1").get(
        "/api/config", headers={"x-tablet-token": "s3cret"}).status_code == 200


def test_the_live_view_of_a_session_streams(client, backend):
    snapshot = client.get("/api/snapshot").json()
    assert snapshot["mood"]["positive"] in (True, False) and snapshot["dialogue"]
    backend.slot.put({"t": 1.0})   # a new snapshot goes out on the stream at once
    with client.stream("GET", "/api/stream") as stream:
        first = next(line for line in stream.iter_lines() if line.startswith("data:"))
    assert '"t":1.0' in first


def test_a_run_keeps_a_bounded_number_of_view_frames(tmp_path):
    config = load_tablet_config()
    config = config.model_copy(update={"replay": config.replay.model_copy(
        update={"frame_period_s": 5.0, "max_frames": 3})})
    clock = {"t": 0.0}
    frames = ViewFrames(tmp_path, lambda: clock["t"], config)
    py_trees.blackboard.Blackboard.storage["/frame"] = np.zeros((240, 320, 3), np.uint8)
    py_trees.blackboard.Blackboard.storage["/detections"] = []
    for step in range(300):   # 30 simulated s at 0.1 s
        clock["t"] = step / 10
        frames()
    kept = sorted(p.name for p in (tmp_path / "view").iterdir())
    assert [frame_time(n) for n in kept] == [0.0, 5.0, 10.0]   # every 5 s, at most 3


def test_a_config_must_name_every_kind(tmp_path):
    bad = tmp_path / "tablet.yaml"
    bad.write_text("buttons:\n  karaoke: {label: Karaoke, line: sing}\n")
    with pytest.raises(ConfigError, match="buttons must name exactly these kinds"):
        load_tablet_config(bad)


def test_a_full_queue_to_the_run_is_refused_not_waited_on():
    config = load_tablet_config()
    config = config.model_copy(update={"server": config.server.model_copy(
        update={"max_queued": 1})})
    client = TestClient(create_app(RunTablet(config)), base_url="http://127.0.0.1")
    assert client.post("/api/feedback", json={"value": 1}).json()["queued"]
    assert client.post("/api/feedback", json={"value": -1}).status_code == 503   # not drained yet
    assert client.get("/api/snapshot").json() == {}       # no tick yet: no snapshot
