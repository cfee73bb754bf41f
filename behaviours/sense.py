"""Sense: turn what happened since the last tick into stimuli on the blackboard.

- people's social events (the simulation's inbox) and the robot's microphones and
  tablet parts: the microphones' blocks of sound go through a voice-activity detector
  (:mod:`behaviours.voice_streams`; a voice starting is ``voice_started``), each utterance
  it ends through the speech recogniser (``ctx.recognizer``), and is a voice heard this tick
  (``voices``: where it came from, how loud, whether words were made out); whom the words
  are said to is judged from them (:mod:`dialogue.addressee`: the robot, unless someone
  else is called by name; a line whose words name no one may still be someone else's,
  which the chat skill tells from the speaker's facing once it turned to them,
  :mod:`behaviours.speaker_gaze`);
  a line for the robot that it made out is queued in ``heard`` (marked ``unclear``
  when the recogniser was unsure, so the chat skill asks for it again; a voice of which no
  words were made out is queued with none, unless it was too faint to be for the robot,
  so that the robot responds to it) and, like a person
  in front, makes the human-present stimulus: someone talking to the robot is an
  interaction; lines for someone else are logged as overheard; a line heard as praise or
  scolding (r_external) is queued in ``feedback`` for :class:`behaviours.feedback.Credit`,
  and praise is also encouragement: it switches the encouragement stimulus on for
  ``encouragement_s``; whoever spoke or gave feedback last is ``person``;
- an emotion counts only on a face the detector found in the current frame (what the face
  at the box's centre shows, :meth:`robot.body.Camera.expression_at`; ``faces``); it
  colours the mood for ``emotion_hold_s`` after it was last seen;
- the facing model reads which way the person in each person box looks (``facings``), for
  the skills that go round to someone's front or tell whom a line was for;
- head-camera frames (RGB, with the depth image beside them) at the scenario's camera rate
  (or the rate a skill steering by person boxes asks for on ``tracking``; or ``idle_rate``
  once no person has been seen in a frame nor heard for ``idle_after_s``) go through the
  detector; a plausible person box whose person is at most ``present_max_distance_m``
  away in the depth image makes the human-present stimulus, held ``present_hold_s`` after
  the last one;
- the motor temperature model gives the overheat stimulus;
- camera frames, the detector and the joints are watched for faults (behaviours/health.py).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from py_trees.common import Status

from behaviours.context import Context
from behaviours.health import SensorHealth
from behaviours.person_range import PersonRange
from behaviours.skill import ContextBehaviour, people_in_view
from behaviours.voice_streams import VoiceStreams
from dialogue.addressee import AddresseeJudge
from dialogue.feedback import FeedbackClassifier
from dialogue.persona import Persona
from dialogue.speech.recognizer import Transcript
from dialogue.speech.words import spoken_words
from perception.detector.yolo import Detection
from robot.geometry import wrap_angle
from robot.percepts import FeedbackEvent, HeardLine, Sound, VoiceHeard

EMOTION_VALUE = {"happy": 1.0, "sad": -1.0, "neutral": 0.0}


def voice_bearing(sound: Sound, words: Transcript) -> float:
    """Where the voice of ``sound`` came from (rad, world frame): found in the head's
    microphones by the beam (``words.direction``, turned by where the head faced), else
    the one-microphone stand-in's ``sound.bearing``, else straight ahead of the head."""
    if words.direction is not None:
        return wrap_angle(sound.heading + words.direction)
    return sound.bearing if sound.bearing is not None else sound.heading


class Sense(ContextBehaviour):
    """Stimuli, heard lines, emotion and camera detections from the simulation's social
    events (the context's inbox), the microphones, the tablet, the head camera and the
    motor temperature."""

    def __init__(self, ctx: Context, name: str = "Sense") -> None:
        super().__init__(name, ctx, reads=("tracking",),
                         writes=("stimuli", "emotion", "line_emotion", "frame", "depth", "frame_t",
                                 "detections", "faces", "facings", "voices", "heard",
                                 "voice_started", "feedback", "person"))
        self._encouraged_until = -np.inf
        self._emotion_until = -np.inf
        self._present_until = -np.inf
        self._noticed = 0.0          # when a person was last seen in a frame or heard
        self.range: PersonRange | None = None
        self.addressee: AddresseeJudge | None = None
        self.streams: VoiceStreams | None = None
        self.health = SensorHealth(self.emit)

    def setup(self, **kwargs: Any) -> None:
        self.range = PersonRange(self.ctx.robot, self.ctx.config.perception)
        self.addressee = AddresseeJudge(Persona.default().config.name, self.ctx.household)
        if self.ctx.recognizer is not None:
            self.streams = VoiceStreams(self.ctx.recognizer.cfg.vad)

    def _social(self) -> None:
        """The household's social events (the inbox), then the microphones' recordings,
        then what was typed or pressed on the tablet."""
        self.bb.voices = []
        robot = self.ctx.robot
        for ev in [*self.ctx.inbox, *robot.microphones.recordings(), *robot.tablet.inputs()]:
            if isinstance(ev, Sound):
                self._sound(ev)
            elif isinstance(ev, HeardLine):      # typed on the tablet: the words as given
                self._noticed = self.now
                self._take(ev)
            elif isinstance(ev, FeedbackEvent):
                self.bb.feedback = [*self.bb.feedback, ev]
                self.bb.person = (ev.person, self.now)
                self.emit("feedback", person=ev.person, value=ev.value, about=ev.about)
        self.ctx.inbox.clear()
        if self.bb.line_emotion is not None:
            self._felt(*self.bb.line_emotion)
        if self.now >= self._emotion_until:
            self.bb.emotion = 0.0

    def _felt(self, emotion: str, since: float) -> None:
        """The feeling of the line just answered (``happy`` or ``sad``), as the human's
        emotion (eq. 3.6) for ``emotion_hold_s``, as a face's would be."""
        self.bb.line_emotion = None
        self.emit("emotion", emotion=emotion, heard=True)
        self.bb.emotion = EMOTION_VALUE[emotion]
        self._emotion_until = max(self._emotion_until, since + self.ctx.config.emotion_hold_s)

    def _sound(self, block: Sound) -> None:
        """A block of the microphones' sound: through the voice-activity detector, whose
        ended utterances are recognised (on the fast hearing path a line comes whole)."""
        if block.words is not None or self.streams is None:
            self._listen(block)
            return
        heard = self.streams.take(block)
        if heard.started:
            self.bb.voice_started = self.now
        for sound in heard.utterances:
            words = self._listen(sound)
            if words is not None and words.text:
                self.streams.made_out(sound.line)
            elif words is not None and heard.whole:
                self._not_made_out(sound, words, heard.voiced)

    def _not_made_out(self, sound: Sound, words: Transcript, voiced: bool) -> None:
        """A recording of which no words were made out. One in which the detector found a
        voice (``voiced``) is queued in ``heard`` as a line with no words, for the robot to
        respond to (the chat skill turns to it, then goes over to the speaker or asks them
        to come closer), unless its speech stood less than ``listening.unmade.min_snr_db``
        over the noise: someone talking elsewhere, whom the robot lets be."""
        respond = voiced and words.snr_db >= self.ctx.config.listening.unmade.min_snr_db
        bearing = voice_bearing(sound, words)
        self.emit("not_made_out", line=sound.line, person=sound.person, voiced=voiced,
                  level_db=round(words.level_db, 1), snr_db=round(words.snr_db, 1),
                  bearing=round(bearing, 3), respond=respond)
        if not respond:
            return
        self._noticed = self.now
        line = HeardLine(sound.line, sound.t, sound.person, "", "robot", bearing, 0.0,
                         unclear=True, snr_db=words.snr_db, by_name=False, ended=self.now)
        self.bb.heard = [*self.bb.heard, line]
        self.bb.person = (line.person, self.now)

    def _listen(self, sound: Sound) -> Transcript | None:
        """Recognise ``sound`` (on the fast hearing path its words come with it); act on
        what was made out of it. What was made out (None: nothing can hear it)."""
        recognizer = self.ctx.recognizer
        if sound.words is not None:
            words = Transcript(" ".join(spoken_words(sound.words)), 1.0, sound.snr_db or 0.0)
            unclear = False
        elif recognizer is None:    # a robot without speech recognition hears nothing
            return None
        else:
            words = recognizer.transcribe(sound.audio, sound.rate)
            unclear = not recognizer.understood(words)
        self.bb.voices = [*self.bb.voices, VoiceHeard(
            sound.line, sound.t, sound.person, voice_bearing(sound, words), words.snr_db,
            bool(words.text))]
        if not words.text:
            self.emit("unheard", line=sound.line, person=sound.person,
                      snr_db=round(words.snr_db, 1))
            return words
        self._noticed = self.now
        assert self.addressee is not None, "setup() first"
        judged = self.addressee.judge(words.text)
        by_name = bool(judged.cue) or self.addressee.names_robot(words.text)
        self._take(HeardLine(sound.line, sound.t, sound.person, words.text, judged.to,
                             voice_bearing(sound, words), words.confidence,
                             unclear=unclear, snr_db=words.snr_db,
                             by_name=by_name, ended=self.now))
        return words

    def _take(self, line: HeardLine) -> None:
        """Queue a line meant for the robot (heard, or typed on its tablet); log it."""
        if line.to_robot:
            self.bb.heard = [*self.bb.heard, line]
            self.bb.person = (line.person, self.now)
            self._present_until = self.now + self.ctx.config.perception.present_hold_s
        self.emit("heard" if line.to_robot else "overheard", line=line.line,
                  person=line.person, text=line.text, to=line.to,
                  bearing=round(line.bearing, 3), confidence=round(line.confidence, 3),
                  unclear=line.unclear)
        if line.to_robot and not line.unclear:
            self._spoken_feedback(line)

    def _spoken_feedback(self, line: HeardLine) -> None:
        """A line that praises or scolds (``dialogue.feedback``) is also feedback, and
        praise is encouragement (the thesis's stimulus, held ``encouragement_s``): the words
        decide, not who said them or why. Only a robot that understands speech (one with a
        dialogue) hears it."""
        if self.ctx.dialogue is None:
            return
        value = FeedbackClassifier.default().value(line.text)
        if value:
            self.bb.feedback = [*self.bb.feedback, FeedbackEvent(line.t, line.person, value,
                                                                 None)]
            self.emit("feedback", person=line.person, value=value, about=None, line=line.line)
        if value > 0:
            self._encouraged_until = self.now + self.ctx.config.encouragement_s
            self.emit("encouraged", person=line.person, text=line.text, line=line.line)

    def _camera(self) -> None:
        ctx, cfg = self.ctx, self.ctx.config.perception
        if self.now - self.bb.frame_t < 1.0 / self._rate() - 1e-6:
            return
        frame, depth = ctx.robot.camera.frame_with_depth()
        ctx.frames_taken += 1
        detections = (self.health.detect(ctx.detector, frame, self.now)
                      if ctx.detector is not None
                      and self.health.frame_usable(frame, ctx.robot.camera.frame_seq, self.now)
                      else [])
        self.bb.frame, self.bb.depth = frame, depth
        self.bb.frame_t, self.bb.detections = self.now, detections
        self.bb.facings = [ctx.facing.facing(frame, d.box)
                           if ctx.facing is not None and d.cls == "person" else None
                           for d in detections]
        people = people_in_view(ctx, detections)
        if people:
            self._noticed = self.now
        self._expressions(frame, detections)
        if any(self._in_front(d) for d in people):
            self._present_until = self.now + cfg.present_hold_s

    def _expressions(self, frame: np.ndarray, detections: list[Detection]) -> None:
        """The expression on each face found in this frame (``faces``); an emotion shown
        colours the mood."""
        height, width = frame.shape[:2]
        camera, min_conf = self.ctx.robot.camera, self.ctx.config.perception.min_conf
        self.bb.faces = [(face, camera.expression_at(*face.centre, width, height))
                         for face in detections if face.cls == "face" and face.conf >= min_conf]
        for _, emotion in self.bb.faces:
            if emotion is None:
                continue
            value = EMOTION_VALUE[emotion]
            if value != self.bb.emotion or self.now >= self._emotion_until:
                self.emit("emotion", emotion=emotion, seen=True)
            self.bb.emotion = value
            self._emotion_until = self.now + self.ctx.config.emotion_hold_s

    def _rate(self) -> float:
        """Camera frames per second now: what a steering skill asks for; else the scenario's
        rate, or the idle rate while no one has been seen or heard for a while (an empty
        room, the dock's wall) but never more than the scenario's."""
        asked = float(self.bb.tracking)
        if asked > 0:
            return asked
        cfg = self.ctx.config.perception
        if self.now - self._noticed >= cfg.idle_after_s:
            return min(cfg.idle_rate, self.ctx.camera_rate)
        return self.ctx.camera_rate

    def _in_front(self, box: Detection) -> bool:
        """Whether the person in ``box`` is a plausible one within the present distance."""
        depth = self.bb.depth
        reach = self.range.distance(depth, box)
        return (reach is not None and reach <= self.ctx.config.perception.present_max_distance_m
                and self.range.plausible(depth, box, reach))

    def update(self) -> Status:
        self._social()
        self._camera()
        self.health.joints(self.ctx.robot.joints.tracking_errors(), self.now)
        self.bb.stimuli = np.array([float(self.ctx.robot.thermal.overheated),
                                    float(self.now <= self._present_until),
                                    float(self.now <= self._encouraged_until)])
        return Status.SUCCESS
