"""A scenario's household as a steppable simulation: PyBullet world, people timeline and the
robot, advanced one scenario step at a time. The behaviour tree and the skill benchmarks
both run on it."""

from __future__ import annotations

import logging
from pathlib import Path

import pybullet as p

from robot.percepts import EmotionEvent, EncourageEvent, SayEvent, SocialEvent
from robot.speaker import speech_seconds
from sim.gaze import TalkGaze
from sim.household_sound import Hearing, HouseholdSound
from sim.reactions import Reactions
from sim.robot import Robot
from sim.robot_config import load_robot_config
from sim.scenario import Scenario, load_scenario
from sim.split_render import SplitRenderer
from sim.world import World

log = logging.getLogger(__name__)

PHYSICS_SUBSTEP_S = 0.05  # joint motors track their ramps to 1e-3 rad at this physics step


class Simulation:
    """Build ``scenario`` in a DIRECT (or GUI) PyBullet client and step it.

    ``step()`` advances the robot's base, joints, battery and motor heat, the physics and the
    people's timeline by one scenario step and returns the social events that fell due. A
    line a person says (or words of encouragement) is recorded as they start it
    (:class:`robot.percepts.Sound`, none when too faint; :mod:`sim.household_sound`) and
    reaches the robot's ``microphones`` part block by block as the time passes; on the fast
    hearing path, whole, once they have finished saying it (people talk at the robot's own
    pace, :func:`robot.speaker.speech_seconds`). An emotion a person shows is on their face
    (:meth:`World.show_emotion`), for the camera to see. With ``camera_helper`` a second
    process renders part of each camera frame (:class:`sim.split_render.SplitRenderer`;
    for a run with two cores). With ``voices_dir`` each recording is also written to
    ``voices_dir/line-NNNN.wav``, NNNN the line's number (:attr:`Sound.line`). ``hearing``
    ``"fast"`` skips the voices and hands the robot audible lines' words with their levels
    (:class:`sim.household_sound.HouseholdSound`).
    """

    def __init__(self, scenario: Scenario, gui: bool = False, robot_config: Path | None = None,
                 camera_helper: bool = False, voices_dir: Path | None = None,
                 hearing: Hearing = "audio") -> None:
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
                           load_robot_config(robot_config), faces=self.world.expression_of)
        self.world.pass_through(self.robot.body_id)
        self.robot.camera.set_lighting(self.world.light.camera_kwargs())
        self.robot.battery.set_level(scenario.robot.battery)
        self.reactions = Reactions(scenario)
        if voices_dir is not None:
            voices_dir.mkdir(parents=True, exist_ok=True)
        self.sound = HouseholdSound(scenario, self.world, self.robot, voices_dir, hearing)
        if camera_helper:
            try:
                self.robot.camera.renderer = SplitRenderer(self.client, self.world, scenario,
                                                    self.robot.cfg,
                                                    self.robot.camera.cfg.helper_share)
            except OSError as exc:   # no processes to spare: the frames are drawn here
                log.warning("no camera helper (%s); frames are drawn in one process", exc)
        self._speaking: list[tuple[float, SayEvent, str]] = []   # (when it ends, line, kind)
        self._repeats: list[SayEvent] = []    # lines people will say again, not begun yet
        self.gaze = TalkGaze(self.world)

    @classmethod
    def from_file(cls, path: str | Path, gui: bool = False) -> Simulation:
        """Load and validate the scenario at ``path`` and build it."""
        return cls(load_scenario(path), gui=gui)

    def step(self) -> list[SocialEvent]:
        """Advance everything by one scenario step; the social events due in it. The lines
        finished in it go to the robot's microphones, as recorded."""
        t_next = (self.steps + 1) * self.dt
        events: list[SocialEvent] = []
        x, y, _ = self.robot.base.pose()
        said = (self.world.advance(self.t, t_next, (x, y))
                + self.reactions.react(t_next, self.world, (x, y)))
        due = [e for e in self._repeats if e.t <= t_next + 1e-9]
        self._repeats = [e for e in self._repeats if e.t > t_next + 1e-9]
        for e in due:
            self._speak(e, "repeat")
        for e in said:
            if isinstance(e, SayEvent):
                self._speak(e, "say")
            elif isinstance(e, EncourageEvent):
                self._speak(SayEvent(e.t, e.person, e.text), "encourage")
            elif isinstance(e, EmotionEvent):
                self.world.show_emotion(e.person, e.emotion)
            else:
                events.append(e)
        done = [(e, kind) for end, e, kind in self._speaking if end <= t_next + 1e-9]
        self._speaking = [s for s in self._speaking if s[0] > t_next + 1e-9]
        if self.sound.hearing == "fast":
            for e, kind in done:
                if sound := self.sound.record(e, kind):
                    self.robot.microphones.record(sound)
        self.robot.microphones.advance(t_next)
        self.gaze.release(t_next)
        self.robot.step(self.dt)
        p.stepSimulation(physicsClientId=self.client)
        self.steps += 1
        self.t = t_next
        return events

    def show(self, action: str | None) -> None:
        """What the robot is doing now, as the people around can see it (they may react:
        :mod:`sim.reactions`)."""
        self.reactions.show(self.t, action)

    def _speak(self, event: SayEvent, kind: str) -> None:
        end = event.t + speech_seconds(event.text)
        self._speaking.append((end, event, kind))
        if self.sound.hearing != "fast" and (sound := self.sound.record(event, kind)):
            lead = self.robot.cfg.acoustics.lead_s
            self.robot.microphones.record(sound, begins=event.t - lead)
        x, y, _ = self.robot.base.pose()
        self.gaze.turn(event, end, (x, y))

    def ask_again(self, line: int, closer: bool = False) -> None:
        """The robot asked for ``line`` to be said again (and, with ``closer``, its speaker
        to come closer): its speaker repeats it, if they do that (``repeat_if_asked``), from
        where they are when they begin (having walked up, asked to come closer)."""
        if (again := self.sound.asked_again(line, self.t, closer)) is not None:
            self._repeats.append(again)

    def line_number(self) -> int:
        """A number for a line that reaches the robot other than by voice (typed on its
        tablet), counted with the lines people say."""
        return self.sound.microphones.number()

    def ask_way(self) -> None:
        """The robot asked for its way to be cleared: the people near it step away
        (:meth:`World.make_way`)."""
        x, y, _ = self.robot.base.pose()
        self.world.make_way(self.t, (x, y))

    def stop_helper(self) -> None:
        """Stop the camera's helper process, if any (later frames are drawn in this one)."""
        if isinstance(self.robot.camera.renderer, SplitRenderer):
            self.robot.camera.renderer.close()

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
