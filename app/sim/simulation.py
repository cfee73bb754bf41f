"""A scenario's household as a steppable simulation: PyBullet world, people timeline and the
robot, advanced one scenario step at a time. The behaviour tree and the skill benchmarks
both run on it."""

from __future__ import annotations

import logging
import math
from pathlib import Path

import pybullet as p

from app.sim.hearing import HeardLine, Microphones
from app.sim.reactions import Reactions
from app.sim.robot import Robot, load_robot_config
from app.sim.scenario import Scenario, load_scenario, voice_of
from app.sim.speech import speech_seconds, write_wav
from app.sim.split_render import SplitRenderer
from app.sim.voices import VoiceError, synthesise
from app.sim.world import EmotionEvent, SayEvent, SocialEvent, World

log = logging.getLogger(__name__)

PHYSICS_SUBSTEP_S = 0.05  # joint motors track their ramps to 1e-3 rad at this physics step


class Simulation:
    """Build ``scenario`` in a DIRECT (or GUI) PyBullet client and step it.

    ``step()`` advances the robot's base, joints, battery and motor heat, the physics and the
    people's timeline by one scenario step and returns the social events that fell due. A
    line a person says comes once they have finished saying it (people talk at the robot's
    own pace, :func:`app.sim.speech.speech_seconds`), as the robot's microphones hear it
    (:class:`app.sim.hearing.HeardLine`). An emotion a person shows is on their face
    (:meth:`World.show_emotion`), for the camera to see. With ``camera_helper`` a second
    process renders part of each camera frame (:class:`app.sim.split_render.SplitRenderer`;
    for a run with two cores). With ``voices_dir`` every line a person says is spoken in their voice
    (:func:`app.sim.scenario.voice_of`) into ``voices_dir/line-NNNN.wav``, NNNN the line's
    number (:attr:`HeardLine.line`).
    """

    def __init__(self, scenario: Scenario, gui: bool = False, robot_config: Path | None = None,
                 camera_helper: bool = False, voices_dir: Path | None = None) -> None:
        self.scenario = scenario
        self.dt = scenario.step
        self.t = 0.0
        self.steps = 0
        self.client = p.connect(p.GUI if gui else p.DIRECT)
        substeps = max(1, round(self.dt / PHYSICS_SUBSTEP_S))
        p.setPhysicsEngineParameter(fixedTimeStep=self.dt, numSubSteps=substeps,
                                    physicsClientId=self.client)
        self.world = World(scenario, self.client)
        start = self.world.robot_start()
        self.robot = Robot(self.client, (start.x, start.y, start.yaw),
                           load_robot_config(robot_config))
        self.world.pass_through(self.robot.body_id)
        self.robot.set_lighting(self.world.light.camera_kwargs())
        self.robot.set_battery(scenario.robot.battery)
        self.microphones = Microphones(self.robot.cfg.microphones, scenario.seed)
        self.reactions = Reactions(scenario)
        self.voices_dir = voices_dir
        if voices_dir is not None:
            voices_dir.mkdir(parents=True, exist_ok=True)
        if camera_helper:
            try:
                self.robot.renderer = SplitRenderer(self.client, self.world, scenario,
                                                    self.robot.cfg,
                                                    self.robot.cfg.camera.helper_share)
            except OSError as exc:   # no processes to spare: the frames are drawn here
                log.warning("no camera helper (%s); frames are drawn in one process", exc)
        self._speaking: list[tuple[float, SayEvent]] = []   # (when it ends, the line)

    @classmethod
    def from_file(cls, path: str | Path, gui: bool = False) -> Simulation:
        """Load and validate the scenario at ``path`` and build it."""
        return cls(load_scenario(path), gui=gui)

    def step(self) -> list[SocialEvent | HeardLine]:
        """Advance everything by one scenario step; the social events due in it (lines
        said as heard)."""
        t_next = (self.steps + 1) * self.dt
        events: list[SocialEvent | HeardLine] = []
        x, y, _ = self.robot.pose()
        said = self.world.advance(self.t, t_next) + self.reactions.react(t_next, self.world, (x, y))
        for e in said:
            if isinstance(e, SayEvent):
                self._speaking.append((e.t + speech_seconds(e.text), e))
            elif isinstance(e, EmotionEvent):     # on their face, for the camera to see
                self.world.show_emotion(e.person, e.emotion)
            else:
                events.append(e)
        events += [self._hear(e) for end, e in self._speaking if end <= t_next + 1e-9]
        self._speaking = [(end, e) for end, e in self._speaking if end > t_next + 1e-9]
        self.robot.step(self.dt)
        p.stepSimulation(physicsClientId=self.client)
        self.steps += 1
        self.t = t_next
        return events

    def show(self, action: str | None) -> None:
        """What the robot is doing now, as the people around can see it (they may react:
        :mod:`app.sim.reactions`)."""
        self.reactions.show(self.t, action)

    def _hear(self, event: SayEvent) -> HeardLine:
        x, y, yaw = self.robot.pose()
        speaker = self.world.people_positions().get(event.person)
        at = (speaker.x, speaker.y) if speaker else (x + math.cos(yaw), y + math.sin(yaw))
        heard = self.microphones.hear(event, (x, y), at)
        if self.voices_dir is not None:
            try:
                samples, rate = synthesise(event.text, voice_of(self.scenario, event.person))
                write_wav(self.voices_dir / f"line-{heard.line:04d}.wav", samples, rate)
            except VoiceError as exc:
                log.warning("%s", exc)
        return heard

    def stop_helper(self) -> None:
        """Stop the camera's helper process, if any (later frames are drawn in this one)."""
        if isinstance(self.robot.renderer, SplitRenderer):
            self.robot.renderer.close()

    def close(self) -> None:
        """Stop the camera's helper, if any, and disconnect the PyBullet client."""
        self.stop_helper()
        if self.client is not None and p.isConnected(self.client):
            p.disconnect(self.client)
        self.client = None

    def __enter__(self) -> Simulation:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
