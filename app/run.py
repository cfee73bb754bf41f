"""``companion run``: one headless household scenario driven by the behaviour tree.

The run folder gets ``events.jsonl`` (flushed per event), ``timeline.csv`` (one row per
homeostasis step), ``dialogue.jsonl``, ``metrics.json``, ``plots/*.png``, ``frames/*.png``
(the camera at key moments), ``tree.txt`` (the tree's shape and its last statuses) and
``scenario.yaml`` (the scenario as run). An interrupted run keeps everything written so far
and still writes its metrics.
"""

from __future__ import annotations

import resource
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import cv2
import numpy as np
import py_trees
import yaml

from app.report import TimelineWriter, compute_metrics, plot_run, write_metrics
from app.sim.scenario import Scenario
from app.sim.simulation import Simulation


class FrameSaver:
    """Saves camera frames as ``frames/NNNN-tTTTT-tag.png``, at most ``limit`` of them."""

    def __init__(self, folder: Path, clock: Any, limit: int = 60) -> None:
        self.folder, self.clock, self.limit, self.count = folder, clock, limit, 0

    def __call__(self, tag: str, frame: np.ndarray) -> str | None:
        if frame is None or self.count >= self.limit:
            return None
        self.folder.mkdir(parents=True, exist_ok=True)
        self.count += 1
        path = self.folder / f"{self.count:04d}-t{self.clock():07.1f}-{tag}.png"
        cv2.imwrite(str(path), cv2.cvtColor(frame, cv2.COLOR_RGB2BGR))
        return path.name


@dataclass
class HouseholdRun:
    """A built run: the simulation, the household services and the tree."""

    scenario: Scenario
    sim: Simulation
    house: Any
    root: py_trees.behaviour.Behaviour
    saver: FrameSaver

    def tick(self) -> None:
        """Advance the simulation one step and tick the tree once."""
        self.house.inbox.extend(self.sim.step())
        self.house.clock.t = self.sim.t
        self.root.tick_once()


def build_run(scenario: Scenario, out: Path, *, gui: bool = False,
              policy_path: Path | None = None, behaviour_config: Path | None = None,
              audio: bool = False) -> HouseholdRun:
    """Build the world, the robot's services (detector, dialogue, question generator,
    policy) and the tree; the run's files go to ``out``. Without a shipped VQG model the
    ask-question skill fails (it has no canned questions)."""
    from app.mind.policy.agent import DEFAULT_POLICY, DQNPolicy
    from behaviours.config import load_behaviour_config
    from behaviours.context import make_household
    from behaviours.tree import build_tree
    from dialogue.factory import household_dialogue
    from perception.detector.config import load_detector_config
    from perception.detector.yolo import YoloDetector
    from perception.vqg.generator import DEFAULT_VQG_MODEL, VqgQuestionGenerator

    out.mkdir(parents=True, exist_ok=True)
    config = load_behaviour_config(behaviour_config)
    policy = DQNPolicy.load(policy_path or DEFAULT_POLICY)
    detector = YoloDetector.from_config(load_detector_config().detect)
    sim = Simulation(scenario, gui=gui)
    saver = FrameSaver(out / "frames", lambda: sim.t)

    def take_photo() -> Path:
        return out / "frames" / str(saver("photo", sim.robot.camera_frame()))

    dialogue = household_dialogue(scenario, lambda: sim.t, out, take_photo)
    questions = (VqgQuestionGenerator.load(DEFAULT_VQG_MODEL, seed=scenario.seed)
                 if DEFAULT_VQG_MODEL.is_file() else None)
    house = make_household(sim, config, detector, events_path=out / "events.jsonl",
                           audio_dir=out / "audio" if audio else None, dialogue=dialogue,
                           questions=questions)
    house.snapshot = saver
    root = build_tree(house, policy, scenario.robot.initial_drives())
    root.setup_with_descendants()
    return HouseholdRun(scenario, sim, house, root, saver)


def run_scenario(scenario: Scenario, out: Path, *, gui: bool = False, progress: bool = True,
                 policy_path: Path | None = None, behaviour_config: Path | None = None,
                 audio: bool = False) -> dict[str, Any]:
    """Run ``scenario`` for its duration and write the run folder; returns the metrics."""
    from tqdm import tqdm

    from behaviours.tree import render

    wall0 = time.perf_counter()
    run = build_run(scenario, out, gui=gui, policy_path=policy_path,
                    behaviour_config=behaviour_config, audio=audio)
    (out / "scenario.yaml").write_text(yaml.safe_dump(scenario.model_dump(mode="json"),
                                                      sort_keys=False))
    sim, house, root, saver = run.sim, run.house, run.root, run.saver
    with sim:
        (out / "tree.txt").write_text(render(root) + "\n")
        timeline = TimelineWriter(out / "timeline.csv")
        bb = py_trees.blackboard.Client(name="run")
        bb.register_key("frame", access=py_trees.common.Access.READ)
        house.events.emit("run_started", scenario=scenario.name, seed=scenario.seed,
                          duration=scenario.duration, step=scenario.step)
        steps, interrupted, seen = round(scenario.duration / scenario.step), False, 0
        try:
            with tqdm(total=scenario.duration, unit="sim s", disable=not progress,
                      bar_format="{l_bar}{bar}| {n:.0f}/{total:.0f} sim s [{elapsed}]") as bar:
                for _ in range(steps):
                    run.tick()
                    timeline.write(house.history)
                    for e in house.events.events[seen:]:
                        if e["kind"] == "action":
                            saver(e["action"], bb.frame)
                    seen = len(house.events.events)
                    bar.update(scenario.step)
        except KeyboardInterrupt:
            interrupted = True
            house.events.emit("interrupted")
        (out / "tree.txt").write_text(render(root) + "\n\nLast tick:\n"
                                      + render(root, show_status=True) + "\n")
        root.stop(py_trees.common.Status.INVALID)
        timeline.close()
        house.events.emit("run_finished", interrupted=interrupted)
        house.events.close()
        metrics = {
            "scenario": scenario.name, "seed": scenario.seed, "duration_s": sim.t,
            "interrupted": interrupted, **compute_metrics(house.history, house.events.events),
            "camera_frames": house.frames_taken,
            "camera_rate_hz": {"default": house.camera_rate,
                               "tracking": house.config.perception.tracking_rate},
            "wall_s": round(time.perf_counter() - wall0, 2),
            "peak_rss_mb": round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, 1),
        }
        h = house.homeostasis
        plot_run(house.history, h.lower, h.upper, h.personality.mood.threshold, out / "plots")
    write_metrics(metrics, out / "metrics.json")
    return metrics
