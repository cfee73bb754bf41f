"""``companion run``: one headless household scenario driven by the behaviour tree.

The run folder gets ``events.jsonl`` (flushed per event), ``timeline.csv`` (one row per
homeostasis step), ``dialogue.jsonl``, ``metrics.json``, ``plots/*.png``, ``frames/*.png``
(the camera at key moments), ``tree.txt`` (the tree's shape and its last statuses) and
``scenario.yaml`` (the scenario as run) and ``view/*.jpg`` (the camera every few seconds, for
``companion view``). Each question the robot asks is scored against the
world's ground truth of what its camera shows (a ``question_truth`` event; the robot never
sees it). The folder is claimed for the run (a lock; an earlier run is replaced only on
request). Every file is written whole: reports atomically, logs a line at a time. A run
stopped by SIGINT or SIGTERM keeps everything written so far and still writes its report.
"""

from __future__ import annotations

import os
import resource
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import cv2
import numpy as np
import yaml
from tqdm import tqdm

from app.faults import FaultInjector, FaultSpec, FaultyDetector, fault_report
from app.report import TimelineWriter, compute_metrics, plot_run, write_metrics
from app.tablet.record import ViewFrames
from app.wiring import make_context
from behaviours.config import load_behaviour_config
from behaviours.context import Context
from behaviours.ticking import SimulationTree
from behaviours.tree import build_tree, render
from core.checkpoint import atomic_write_bytes
from core.profiling import Profile
from core.run_folder import RunFolderError, claim, release
from core.signals import shielded, signal_name, terminable
from dialogue.factory import household_dialogue
from dialogue.speech.recognizer import SpeechRecognizer
from mind.personality import load_personality
from mind.policy.agent import DQNPolicy
from mind.policy.config import DEFAULT_POLICY
from mind.preferences.memory import Memory, load_memory
from perception.detector.config import load_detector_config
from perception.detector.yolo import YoloDetector
from perception.facing.config import DEFAULT_FACING_MODEL
from perception.facing.model import FacingEstimator
from perception.vqg.generator import DEFAULT_VQG_MODEL, VqgQuestionGenerator
from perception.vqg.scene import SceneGraph
from perception.vqg.training.data_config import load_vqg_data_config
from perception.vqg.training.household import check_occasion, household_scene, judge_question
from robot.dances import song_names
from sim.household_sound import Hearing
from sim.scenario import Scenario, load_scenario
from sim.simulation import Simulation

RESOURCE_PERIOD_S = 300.0   # simulated seconds between two `resources` events


class FrameSaver:
    """Saves camera frames as ``frames/NNNN-tTTTT-tag.png``, each written whole: at most
    ``limit`` key moments, and at most ``photo_limit`` photos people asked for. With a scene
    graph, the world's account of what the frame shows goes beside it as
    ``NNNN-tTTTT-tag.json`` (``companion eval vqg --household`` reads both)."""

    def __init__(self, folder: Path, clock: Any, limit: int = 60, photo_limit: int = 200
                 ) -> None:
        self.folder, self.clock, self.count = folder, clock, 0
        self.left = {"key": limit, "photo": photo_limit}

    def __call__(self, tag: str, frame: np.ndarray, scene: SceneGraph | None = None
                 ) -> str | None:
        """:meth:`save`."""
        return self.save(tag, frame, scene)

    def save(self, tag: str, frame: np.ndarray, scene: SceneGraph | None = None
             ) -> str | None:
        """Save ``frame`` (and ``scene`` beside it) under ``tag``; its file name, or None
        when none is left of its kind or it can't be encoded."""
        kind = "photo" if tag == "photo" else "key"
        if frame is None or self.left[kind] <= 0:
            return None
        ok, png = cv2.imencode(".png", cv2.cvtColor(frame, cv2.COLOR_RGB2BGR))
        if not ok:
            return None
        self.left[kind] -= 1
        self.count += 1
        path = self.folder / f"{self.count:04d}-t{self.clock():07.1f}-{tag}.png"
        atomic_write_bytes(path, png.tobytes())
        self.describe(path.name, scene)
        return path.name

    def describe(self, name: str | None, scene: SceneGraph | None) -> None:
        """Write ``scene`` beside the saved frame ``name`` (nothing when either is None)."""
        if name is not None and scene is not None:
            atomic_write_bytes((self.folder / name).with_suffix(".json"),
                               scene.to_json().encode())


@dataclass
class HouseholdRun:
    """A built run: the simulation, the behaviours' context and the tree, set up (its
    ``tick()`` steps the simulation, then ticks the behaviours)."""

    scenario: Scenario
    sim: Simulation
    ctx: Context
    tree: SimulationTree
    saver: FrameSaver
    out: Path
    timeline: TimelineWriter | None = None
    profile: Profile | None = None


@dataclass(frozen=True)
class RunOptions:
    """How a household run is made, beyond its scenario.

    ``gui``: a PyBullet window. ``policy_path``: the DQN (None: the shipped one).
    ``behaviour_config``: YAML over the behaviour defaults. ``audio``: sentences spoken into
    WAV files. ``faults``: a :class:`~app.faults.FaultInjector` breaks things as the run goes
    (before each tick), and an exception inside a behaviour fails that behaviour instead of
    the run. ``adapt``: the robot learns from feedback during the run, starting from the
    household memory file ``memory`` (saved as it learns) or, without one, from nothing.
    ``threads``: the detector's CPU threads (None: the detector config's), and the cores the
    run may use: with two or more a helper process renders part of each camera frame
    (:class:`~sim.split_render.SplitRenderer`; None: the machine's cores). ``profile``:
    time the run's parts (:mod:`core.profiling`). ``tablet``: an
    :class:`app.tablet.run_link.RunTablet` that a web server feeds during the run.
    ``hearing``: ``"fast"`` hears audible lines as said, from the acoustics' levels alone,
    with no voice synthesised or recognised (sweeps; docs/speech.md says what it overstates).
    """

    gui: bool = False
    policy_path: Path | None = None
    behaviour_config: Path | None = None
    audio: bool = False
    faults: FaultSpec | None = None
    memory: Path | None = None
    adapt: bool = True
    threads: int | None = None
    profile: bool = False
    tablet: Any = None
    hearing: Hearing = "audio"


def build_run(scenario: Scenario, out: Path, options: RunOptions = RunOptions()
              ) -> HouseholdRun:
    """Build the world, the robot's services (detector, facing model, dialogue, question
    generator, policy) and the tree, as ``options`` say; the run's files go to ``out``.
    Without a shipped VQG model the ask-question skill fails (it has no canned questions)."""
    check_occasion(scenario)   # before anything is built or written
    memory = options.memory
    household = load_memory(memory, scenario.name) if memory is not None else None
    out.mkdir(parents=True, exist_ok=True)
    config = load_behaviour_config(options.behaviour_config)
    policy = DQNPolicy.load(options.policy_path or DEFAULT_POLICY)
    detect = load_detector_config().detect
    if options.threads is not None:
        detect = detect.model_copy(update={"threads": options.threads})
    detector: Any = YoloDetector.from_config(detect)
    cores = options.threads or os.cpu_count() or 1
    sim = Simulation(scenario, gui=options.gui, camera_helper=cores >= 2 and not options.gui,
                     voices_dir=out / "audio" / "people" if options.audio else None,
                     hearing=options.hearing)
    saver = FrameSaver(out / "frames", lambda: sim.t)

    def take_photo() -> Path:
        name = saver("photo", sim.robot.camera.frame())
        if name is None:
            raise RuntimeError(f"no photo saved (camera frame missing, or "
                               f"{saver.left['photo']} photos left)")
        return out / "frames" / name

    dialogue = household_dialogue(scenario, lambda: sim.t, out, take_photo,
                                  songs=song_names(config.sing_dance.resolved_routines()))
    questions = (VqgQuestionGenerator.load(DEFAULT_VQG_MODEL, seed=scenario.seed)
                 if DEFAULT_VQG_MODEL.is_file() else None)
    facing = (FacingEstimator.load(DEFAULT_FACING_MODEL) if DEFAULT_FACING_MODEL.is_file()
              else None)
    ctx = make_context(sim, config, detector, events_path=out / "events.jsonl",
                       audio_dir=out / "audio" if options.audio else None, dialogue=dialogue,
                       questions=questions, facing=facing, recognizer=SpeechRecognizer(
                           microphones=sim.robot.cfg.acoustics.microphones))
    ctx.snapshot, ctx.contain_faults = saver, True
    if options.adapt:
        ctx.memory, ctx.memory_path = household or Memory(scenario.name), memory
        dialogue.memory = ctx.memory      # what people tell it, kept with their preferences
    profile = Profile() if options.profile else None
    if profile is not None:
        profile.wrap(policy, "q_values", "policy")
    tree = SimulationTree(build_tree(ctx, policy, scenario.robot.initial_drives()), sim, ctx)
    if options.faults is not None:
        injector = FaultInjector(options.faults, sim, ctx.events)
        ctx.detector = FaultyDetector(detector, injector)
        injector.at_load(dialogue)
        tree.add_pre_tick_handler(lambda _: injector.apply(
            sim.t, ctx.steps.last_action))
    run = HouseholdRun(scenario, sim, ctx, tree, saver, out, profile=profile)
    tree.add_post_tick_handler(ViewFrames(out, ctx.clock))
    if options.tablet is not None:
        options.tablet.attach(run)
    if profile is not None:
        _instrument(run, profile)
    tree.setup()
    return run


def _instrument(run: HouseholdRun, profile: Profile) -> None:
    """Time the parts of ``run``: the simulation step (physics, people), the camera's
    renders, each model, the speech, the writers and the tree's own ticking."""
    sim, ctx = run.sim, run.ctx
    profile.wrap(sim, "step", "simulation step")
    for method in ("frame", "frame_with_depth"):
        profile.wrap(sim.robot.camera, method, "render")
    profile.wrap(ctx.detector, "detect", "detect")
    profile.wrap(ctx.facing, "facing", "facing model")
    profile.wrap(ctx.dialogue, "respond", "dialogue")
    profile.wrap(ctx.recognizer, "transcribe", "speech recognition")
    profile.wrap(ctx.questions, "ask", "questions (VQG)")
    profile.wrap(ctx.speaker, "say", "speech")
    profile.wrap(ctx.events, "emit", "writing")
    profile.wrap(run.saver, "save", "writing")
    profile.wrap(run.tree, "tick", "tree")


def prepare_scenario(path: Path, *, duration: float | None = None, seed: int | None = None,
                     loop: bool = False, personality: Path | None = None) -> Scenario:
    """The scenario at ``path`` with a run's overrides: ``duration``, ``seed``, a looping
    timeline (``loop``: every scenario duration) and another ``personality`` file."""
    scenario = load_scenario(path)
    update: dict[str, Any] = {"loop_period": scenario.duration} if loop else {}
    if duration is not None:
        update["duration"] = duration
    if seed is not None:
        update["seed"] = seed
    if personality is not None:
        load_personality(personality)   # checked now, named if broken
        update["personality"] = personality.resolve()
    return scenario.model_copy(update=update)


def run_scenario(scenario: Scenario, out: Path, options: RunOptions = RunOptions(), *,
                 progress: bool = True, overwrite: bool = False,
                 tags: dict[str, Any] | None = None) -> dict[str, Any]:
    """Run ``scenario`` for its duration in the run folder ``out`` (claimed first:
    :func:`core.run_folder.claim`, ``overwrite`` replacing an earlier run) as ``options``
    say, and return the metrics (with ``tags`` added, e.g. the sweep entry it ran; with
    ``options.profile``, the time of each part under ``profile``). SIGINT or SIGTERM ends the
    run early: the report is still written and ``metrics["interrupted_by"]`` names the
    signal. A failed write (a full disk) stops the run with a
    :class:`~core.run_folder.RunFolderError`; what was written stays whole."""
    wall0 = time.perf_counter()
    check_occasion(scenario)   # before anything is built or written
    claim(out, overwrite)
    try:
        run = build_run(scenario, out, options)
        atomic_write_bytes(out / "scenario.yaml", yaml.safe_dump(
            scenario.model_dump(mode="json"), sort_keys=False).encode())
        with run.sim:
            interrupt = _play(run, progress, wall0)
            with shielded():
                return _finish(run, out, interrupt, wall0, tags or {})
    except OSError as exc:
        raise RunFolderError(f"{exc.filename or out}: writing the run failed "
                             f"({exc.strerror or exc}); the files written before it are kept"
                             ) from None
    finally:
        release(out)


def resident_mb() -> float:
    """This process's resident memory now (MB), from /proc/self/statm."""
    pages = int(Path("/proc/self/statm").read_text().split()[1])
    return round(pages * resource.getpagesize() / 2**20, 1)


def _play(run: HouseholdRun, progress: bool, wall0: float) -> KeyboardInterrupt | None:
    """Tick the run to its end, or until SIGINT/SIGTERM (returned)."""
    scenario, sim, ctx, tree, saver = run.scenario, run.sim, run.ctx, run.tree, run.saver
    visibility = load_vqg_data_config().visibility
    atomic_write_bytes(run.out / "tree.txt", (render(tree.root) + "\n").encode())
    run.timeline = TimelineWriter(run.out / "timeline.csv")
    scene_of = household_scene
    if run.profile is not None:
        run.profile.add("start-up", time.perf_counter() - wall0)
        run.profile.wrap(run.timeline, "write", "writing")
        scene_of = run.profile.timed(household_scene, "ground truth (scoring)")
    ctx.events.emit("run_started", scenario=scenario.name, seed=scenario.seed,
                    duration=scenario.duration, step=scenario.step)
    seen, next_sample = 0, 0.0

    def record() -> None:
        """After each tick: the timeline's rows, what people said, the photos and the
        ground truth of what the robot did and asked, the memory now and then."""
        nonlocal seen, next_sample
        run.timeline.write(ctx.steps.take())
        for said in sim.sound.said:   # what people said, for scoring the hearing
            ctx.events.emit("line_said", **said)
        sim.sound.said.clear()
        for e in ctx.events.events[seen:]:
            if e["kind"] == "action":
                frame, scene = scene_of(sim, visibility)
                saver(e["action"], frame, scene)
            elif e["kind"] == "question":  # scored by the world's ground truth
                _, scene = scene_of(sim, visibility)
                saver.describe(e["frame"], scene)
                ctx.events.emit("question_truth", question=e["text"],
                                **judge_question(e["text"], scene))
        seen = len(ctx.events.events)
        if sim.t >= next_sample:   # memory over time, for soaks (bench/bench_soak.py)
            ctx.events.emit("resources", rss_mb=resident_mb(),
                            wall_s=round(time.perf_counter() - wall0, 1))
            next_sample += RESOURCE_PERIOD_S
        bar.update(scenario.step)

    try:
        with terminable(), tqdm(total=scenario.duration, unit="sim s",
                                disable=None if progress else True,  # None: not off a tty
                                bar_format="{l_bar}{bar}| {n:.0f}/{total:.0f} sim s "
                                "[{elapsed}]") as bar:
            tree.run(steps=round(scenario.duration / scenario.step), after_tick=record)
    except KeyboardInterrupt as interrupt:
        ctx.events.emit("interrupted", signal=signal_name(interrupt))
        return interrupt
    return None


def _finish(run: HouseholdRun, out: Path, interrupt: KeyboardInterrupt | None, wall0: float,
            tags: dict[str, Any]) -> dict[str, Any]:
    """Stop the tree and write the report: tree.txt, metrics.json, then the plots."""
    scenario, sim, ctx, tree = run.scenario, run.sim, run.ctx, run.tree
    sim.stop_helper()   # its memory is not needed while the plots are drawn
    atomic_write_bytes(out / "tree.txt", (render(tree.root) + "\n\nLast tick:\n" + render(
        tree.root, show_status=True) + "\n").encode())
    tree.stop()
    run.timeline.write(ctx.steps.take())   # the rows of a tick cut short by a signal
    run.timeline.close()
    ctx.events.emit("run_finished", interrupted=interrupt is not None)
    ctx.events.close()
    metrics = {
        "scenario": scenario.name, "seed": scenario.seed, "duration_s": sim.t,
        "interrupted": interrupt is not None,
        "interrupted_by": signal_name(interrupt) if interrupt is not None else None,
        "hearing": sim.sound.hearing,
        **compute_metrics(ctx.steps, ctx.events.events),
        "faults": fault_report(ctx.events.events),
        "camera_frames": ctx.frames_taken,
        "camera_rate_hz": {"default": ctx.camera_rate,
                           "tracking": ctx.config.perception.tracking_rate,
                           "idle": min(ctx.config.perception.idle_rate, ctx.camera_rate)},
        "wall_s": round(time.perf_counter() - wall0, 2),
        "peak_rss_mb": round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, 1),
        **tags,
    }
    if run.profile is not None:   # the report's own writing is counted under "other"
        metrics["profile"] = run.profile.report(time.perf_counter() - wall0)
    write_metrics(metrics, out / "metrics.json")
    h = ctx.homeostasis
    plot_run(out / "timeline.csv", h.lower, h.upper, h.personality.mood.threshold, out / "plots")
    return metrics
