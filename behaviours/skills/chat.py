"""Chat: dialogue turns with the people who talk to the robot or stand in front of it.

Spoken to, the robot turns to the voice (:class:`behaviours.listening.FaceSpeaker`) and
answers each queued line (``heard``, oldest first; see :func:`behaviours.listening.pending`)
through the dialogue manager, the reply styled by the current mood. It answers once its
head points at the voice, or after ``listening.answer_wait_s``; a line whose words named
no one it answers unless everyone seen near the voice, once the head turned, looks away
(:mod:`behaviours.speaker_gaze`; the line is then logged as overheard). What a reply asks of the
robot is carried out: a song goes to ``request`` (Decide starts sing and dance next, and
the chat ends once the reply is said), as does going over to someone whose voice it could
not make out (find people towards the voice), and a tablet page is shown (``tablet`` event). Started
by the policy with nothing to answer, the robot opens with ``chat.opener``; then it needs a
person in front, or it fails at once. The action lasts its Table 4.2 duration (Relieve).
"""

from __future__ import annotations

import math
from typing import Any

import py_trees
from py_trees.common import Status

from behaviours.context import Context
from behaviours.listening import FaceSpeaker, head_error, pending, reply_to
from behaviours.person_range import PersonRange
from behaviours.skill import ContextBehaviour, Relieve, facing_of, people_in_view
from behaviours.speaker_gaze import SpeakerGaze
from robot.percepts import HeardLine

HUMAN_PRESENT = 1  # index in the stimuli vector
REQUESTED = ("sing_dance", "find_people")   # actions a reply may ask for, started next


class SpokenTo(ContextBehaviour):
    """SUCCESS while a line waits to be answered, else FAILURE."""

    def __init__(self, ctx: Context, name: str = "Spoken to?") -> None:
        super().__init__(name, ctx, reads=("heard",))

    def update(self) -> Status:
        lines = pending(self.bb.heard, self.now, self.ctx.config.chat.max_heard_age_s)
        return Status.SUCCESS if lines else Status.FAILURE


class SomeoneInFront(ContextBehaviour):
    """SUCCESS while the human-present stimulus is on, else FAILURE (and an event)."""

    def __init__(self, ctx: Context, name: str = "Someone in front?") -> None:
        super().__init__(name, ctx, reads=("stimuli",))

    def update(self) -> Status:
        if self.bb.stimuli[HUMAN_PRESENT] > 0:
            return Status.SUCCESS
        self.emit("no_one_here")
        return Status.FAILURE


class Converse(ContextBehaviour):
    """Answer queued lines one at a time, each once the previous reply has been said and
    the head points at its voice. A voice that starts while the robot talks
    (``voice_started``) stops what it is saying: it listens instead. SUCCESS when a reply
    asked for another action and has been said; otherwise RUNNING."""

    def __init__(self, ctx: Context, name: str = "Converse") -> None:
        super().__init__(name, ctx, reads=("mood", "frame", "frame_t", "depth", "detections",
                                           "facings", "voice_started"),
                         writes=("heard", "listening_to", "request", "line_emotion"))
        self._busy_until = 0.0
        self._talking_since = 0.0       # when what it is saying began
        self._turned_at: float | None = None   # when the robot began turning to the voice
        self.gaze: SpeakerGaze | None = None

    def setup(self, **kwargs: Any) -> None:
        ctx = self.ctx
        if ctx.dialogue is None:
            raise ValueError("the chat skill needs ctx.dialogue (a DialogueManager)")
        if ctx.facing is not None and ctx.detector is not None:
            self.gaze = SpeakerGaze(PersonRange(ctx.robot, ctx.config.perception),
                                    ctx.config.listening.gaze)

    def initialise(self) -> None:
        self._busy_until, self._turned_at = self.now, None
        self._talking_since = self.now
        self.bb.listening_to = None
        if not self._pending():
            self._busy_until += self.ctx.speaker.say(self.ctx.config.chat.opener,
                                                     behaviour=self.name)

    def _pending(self) -> list[HeardLine]:
        return pending(self.bb.heard, self.now, self.ctx.config.chat.max_heard_age_s)

    def _ready(self, line: HeardLine) -> bool:
        """Turned to the voice of ``line`` (or waited long enough for the head)."""
        cfg = self.ctx.config.listening
        if self.bb.listening_to != line.bearing:
            self.bb.listening_to, self._turned_at = line.bearing, self.now
        aligned = abs(head_error(self.ctx, line.bearing)) <= math.radians(
            cfg.answer_tolerance_deg)
        return aligned or self.now - self._turned_at >= cfg.answer_wait_s

    def _for_robot(self, line: HeardLine) -> bool | None:
        """Whether ``line`` is the robot's to answer: its words said so; else unless the
        first frame that takes in the voice's surroundings, within ``gaze.within_s`` of the
        line's end, shows everyone near the voice looking away
        (:mod:`behaviours.speaker_gaze`). None while that frame is awaited, for at most
        ``answer_wait_s`` since the robot began turning."""
        if line.by_name or self.gaze is None or self.now - line.ended > self.gaze.cfg.within_s:
            return True
        frame = self.bb.frame
        if (self.bb.frame_t == self.now and frame is not None
                and self.gaze.covers(line.bearing, frame)):
            detections, facings = self.bb.detections, self.bb.facings
            people = people_in_view(self.ctx, detections)
            return not self.gaze.looks_away(line.bearing, frame, self.bb.depth, people,
                                            lambda box: facing_of(detections, facings, box))
        waited = self.now - self._turned_at >= self.ctx.config.listening.answer_wait_s
        return True if waited else None

    def update(self) -> Status:
        lines = self._pending()
        self.bb.heard = lines
        if self.now < self._busy_until:
            if self.bb.voice_started <= self._talking_since:
                return Status.RUNNING
            self.emit("spoken_over", after_s=round(self.now - self._talking_since, 2),
                      unsaid_s=round(self._busy_until - self.now, 2))
            self._busy_until = self.now
        if self.bb.request is not None:
            return Status.SUCCESS
        if not lines or not self._ready(lines[0]):
            return Status.RUNNING
        said = lines[0]
        if (for_robot := self._for_robot(said)) is None:
            return Status.RUNNING
        self.bb.heard = lines[1:]
        if not for_robot:
            self.emit("overheard", line=said.line, person=said.person, text=said.text,
                      to="someone", bearing=round(said.bearing, 3), seen_facing_away=True)
            self.bb.listening_to = None
            return Status.RUNNING
        reply, seconds = reply_to(self, said, self.bb.mood["positive"], can_move=True)
        self._talking_since, self._busy_until = self.now, self.now + seconds
        if reply.action is not None and reply.action.name in REQUESTED:
            self.bb.request = reply.action
        return Status.RUNNING


class LookAhead(ContextBehaviour):
    """On exit, stop listening and bring the head back to centre."""

    def __init__(self, ctx: Context, name: str = "Look ahead") -> None:
        super().__init__(name, ctx, writes=("listening_to",))

    def update(self) -> Status:
        return Status.RUNNING

    def terminate(self, new_status: Status) -> None:
        self.bb.listening_to = None
        self.ctx.robot.head.look(yaw=0.0, speed=self.ctx.config.listening.head_speed)


def build(ctx: Context) -> py_trees.behaviour.Behaviour:
    """The chat subtree: someone to talk to (spoken to, or a person in front), then talk
    (turn to the voice, converse) for the action's duration (its setup needs
    ``ctx.dialogue``)."""
    anyone = py_trees.composites.Selector("Anyone to talk to?", memory=False,
                                          children=[SpokenTo(ctx), SomeoneInFront(ctx)])
    talk = py_trees.composites.Parallel(
        "Talk", policy=py_trees.common.ParallelPolicy.SuccessOnOne(),
        children=[Converse(ctx), FaceSpeaker(ctx), LookAhead(ctx),
                  Relieve("Chat relieves", ctx, "chat")])
    return py_trees.composites.Sequence("Chat", memory=True, children=[anyone, talk])
