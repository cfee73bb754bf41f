"""A line the recogniser is unsure of is asked for again; when its speech hardly stood over
the noise at the microphones (``listening.closer_below_snr_db``) the robot asks its speaker
to come closer instead, and a line it is sure of is answered however faint."""

from __future__ import annotations

import py_trees
import pytest

from behaviours.blackboard import seed
from behaviours.config import load_behaviour_config
from behaviours.context import Context, SimClock
from behaviours.listening import reply_to
from behaviours.skill import ContextBehaviour
from core.events import EventLog
from dialogue.manager import DialogueManager
from dialogue.qa.bot import QABot
from mind.homeostasis import Homeostasis
from mind.personality import DRIVES, load_personality
from robot.percepts import HeardLine
from robot.speaker import Speaker


class Chat(ContextBehaviour):
    """A behaviour that answers lines through :func:`reply_to` (its update does nothing)."""

    def update(self) -> py_trees.common.Status:
        return py_trees.common.Status.SUCCESS


@pytest.fixture
def ctx(tmp_path) -> Context:
    py_trees.blackboard.Blackboard.clear()
    clock = SimClock(dt=0.1)
    cfg = load_behaviour_config()
    listening = cfg.listening.model_copy(update={"closer_below_snr_db": 15.0})
    context = Context(robot=None, floor_plan=None, homeostasis=Homeostasis(load_personality()),
                      config=cfg.model_copy(update={"listening": listening}), clock=clock,
                      events=EventLog(None, clock), speaker=None)
    context.speaker = Speaker(context.events)
    context.dialogue = DialogueManager(QABot.offline(out_dir=tmp_path), min_confidence=0.15)
    seed(context, dict.fromkeys(DRIVES, 0.5))
    return context


@pytest.mark.parametrize(("snr_db", "confidence", "expected"), [
    (10.0, 0.1, "come_closer"), (25.0, 0.1, "say_again"), (10.0, 0.6, "time")])
def test_an_unclear_line_is_asked_again_and_a_faint_one_brings_its_speaker_closer(
        ctx, snr_db, confidence, expected):
    asked = []
    ctx.ask_again = lambda line, closer: asked.append((line, closer))
    line = HeardLine(1, ctx.now, "Daniel", "What time is it?", "robot", 0.0, confidence=confidence,
                     unclear=confidence < 0.15, snr_db=snr_db)
    reply, _ = reply_to(Chat("Chat", ctx), line, positive=True)
    said = ctx.events.of_kind("say")[-1]
    if expected == "time":
        assert reply.route == "time" and asked == []
        return
    assert reply.route == "say_again" and asked == [(1, expected == "come_closer")]
    closer = said["text"] == ctx.config.listening.come_closer
    assert closer == (expected == "come_closer")
