"""Listening: the lines people said to the robot, and the two reactions to them that run
outside any one skill.

- :func:`pending`: the queued lines still worth answering (a line older than
  ``chat.max_heard_age_s`` is dropped, unless the robot promised to answer it);
- :func:`reply_to`: answer one line through the dialogue manager (the chat skill's
  Converse and Promise); a voice of which no words were made out gets a response too
  (:func:`not_made_out`): the robot goes over to its speaker, or asks them to come closer;
- :class:`Promise`: while a safety action must finish (charging on critical energy, resting
  when overheated) the base stays put, but the robot still talks: it answers each new line
  by voice at once, and what a reply asks of its body (a song and dance) it promises for
  afterwards; Decide starts that request once the safety action is over;
- :class:`FaceSpeaker`: turns the head, then the base, to the voice being answered.
"""

from __future__ import annotations

import dataclasses
import math

from py_trees.common import Status

from behaviours.config import ListeningConfig
from behaviours.context import Context
from behaviours.skill import ContextBehaviour
from dialogue.manager import Reply
from dialogue.qa.base import Action
from mind.preferences.memory import save_memory
from robot.geometry import wrap_angle
from robot.percepts import HeardLine

LINE_EMOTION = {"positive": "happy", "negative": "sad"}   # a line's feeling as an expression


def pending(lines: list[HeardLine], now: float, max_age_s: float) -> list[HeardLine]:
    """The lines to answer, oldest first: the promised ones and those at most ``max_age_s``
    old."""
    return [line for line in lines if line.promised or now - line.t <= max_age_s]


def head_error(ctx: Context, bearing: float) -> float:
    """How far (rad) the head points from ``bearing`` (world frame), given the base's yaw
    and the head's yaw."""
    yaw = ctx.robot.base.pose()[2] + ctx.robot.head.angles()[0]
    return wrap_angle(bearing - yaw)


def not_made_out(cfg: ListeningConfig, said: HeardLine, can_move: bool) -> Reply:
    """The response to ``said``, a voice of which no words were made out: when the robot
    may move, it says it is coming over and asks for find people towards the voice (the
    reply's action; once there it asks for the line again), else it asks the speaker to
    come closer (a ``say_again`` reply)."""
    if not can_move:
        return Reply(cfg.come_closer, "say_again", found=False)
    return Reply(cfg.unmade.coming_over, "coming_over", found=False,
                 action=Action("find_people", {"bearing": said.bearing, "line": said.line}))


def reply_to(behaviour: ContextBehaviour, said: HeardLine, positive: bool,
             promise: str = "", can_move: bool = False) -> tuple[Reply, float]:
    """Answer the line ``said`` through the dialogue manager in the robot's mood: say the
    reply (followed by ``promise`` when the reply asks for an action, which the caller
    starts later) and show its tablet page. A line the recogniser was unsure of is asked
    for again, and its speaker hears the request; when its speech hardly stood over the
    noise (``listening.closer_below_snr_db``), the robot asks them to come closer too. A
    voice of which no words were made out gets :func:`not_made_out` (``can_move``: the
    robot may go over to its speaker). A care signal in the line is a ``care_alert`` event
    (who, what, the line); the feeling the line shares goes on ``line_emotion``, which
    Sense takes as the human's emotion (eq. 3.6); what the speaker told about themselves
    is kept in the household memory (saved at once). Each person has their own
    conversation. The reply, and how long saying it takes (s)."""
    ctx, mood = behaviour.ctx, "positive" if positive else "negative"
    cfg = ctx.config.listening
    reply = (ctx.dialogue.respond(said.text, mood, ctx.dialogue.context_of(said.person),
                                  confidence=said.confidence, person=said.person)
             if said.made_out else not_made_out(cfg, said, can_move))
    text = f"{reply.text} {promise}" if promise and reply.action is not None else reply.text
    if reply.route == "say_again":
        closer = not said.made_out or said.snr_db < cfg.closer_below_snr_db
        text = cfg.come_closer if closer else text
        ctx.ask_again(said.line, closer)
    seconds = ctx.speaker.say(text, behaviour=behaviour.name, to=said.person, line=said.line,
                              in_reply_to=said.text, route=reply.route, found=reply.found,
                              mood=mood, act=reply.act)
    if reply.tablet:
        behaviour.emit("tablet", page=reply.tablet, line=said.line)
    if reply.care:
        behaviour.emit("care_alert", person=said.person, care=reply.care, line=said.line,
                       text=said.text)
    if reply.emotion:
        behaviour.bb.line_emotion = (LINE_EMOTION[reply.emotion], behaviour.now)
    if reply.remembered:
        behaviour.emit("remembered", person=said.person, kinds=list(reply.remembered))
        if ctx.memory is not None and ctx.memory_path is not None:
            save_memory(ctx.memory, ctx.memory_path)
    return reply, seconds


class Promise(ContextBehaviour):
    """Always SUCCESS. While ``must_finish``: answer each new line at once by voice, one at a
    time, the base staying put; a reply asking for a song is followed by the promise to do
    it once the safety action is over (``request`` is set; Decide starts it then). Without a
    dialogue manager, tell each new speaker that the robot will come back to them, and mark
    their lines promised (the chat answers them afterwards)."""

    def __init__(self, ctx: Context, name: str = "Promise") -> None:
        super().__init__(name, ctx, reads=("must_finish", "action", "mood"),
                         writes=("heard", "request", "line_emotion"))
        self._busy_until = -math.inf

    def update(self) -> Status:
        fresh = [line for line in self.bb.heard if not line.promised]
        if not self.bb.must_finish or not fresh or self.now < self._busy_until:
            return Status.SUCCESS
        cfg = self.ctx.config.listening
        activity = cfg.activities.get(self.bb.action, "finish this")
        if self.ctx.dialogue is None:
            self.ctx.speaker.say(cfg.promise.format(activity=activity), behaviour=self.name,
                                 to=fresh[0].person, lines=[line.line for line in fresh])
            self.bb.heard = [dataclasses.replace(line, promised=True) if not line.promised
                             else line for line in self.bb.heard]
            return Status.SUCCESS
        said = fresh[0]
        reply, seconds = reply_to(self, said, self.bb.mood["positive"],
                                  cfg.promise_action.format(activity=activity))
        self._busy_until = self.now + seconds
        self.bb.heard = [line for line in self.bb.heard if line is not said]
        if reply.action is not None and reply.action.name == "sing_dance":
            self.bb.request = reply.action
        return Status.SUCCESS


class FaceSpeaker(ContextBehaviour):
    """Turn to ``listening_to``: the head at once (within its joint range), the base after
    it so that the head comes back to centre. RUNNING until stopped; the base stops when it
    faces the voice, or when there is no voice to face."""

    def __init__(self, ctx: Context, name: str = "Face the speaker") -> None:
        super().__init__(name, ctx, reads=("listening_to",))

    def update(self) -> Status:
        robot, cfg = self.ctx.robot, self.ctx.config.listening
        bearing = self.bb.listening_to
        if bearing is None:
            robot.base.set_velocity(0.0, 0.0, 0.0)
            return Status.RUNNING
        off_base = wrap_angle(bearing - robot.base.pose()[2])
        lo, hi = robot.head.yaw_limits()
        robot.head.look(yaw=min(max(off_base, lo), hi), speed=cfg.head_speed)
        facing = abs(off_base) <= math.radians(cfg.facing_tolerance_deg)
        turn = 0.0 if facing else math.copysign(min(cfg.turn_speed, cfg.turn_gain
                                                    * abs(off_base)), off_base)
        robot.base.set_velocity(0.0, 0.0, turn)
        return Status.RUNNING

    def terminate(self, new_status: Status) -> None:
        self.ctx.robot.base.set_velocity(0.0, 0.0, 0.0)
