"""How tall a standing person's box is at each distance, as find_people sees it: the robot
stands in the living room with its head at ``find_people.head_pitch`` and one person faces it
from a range of distances. Prints the label box (tight extent of the person's pixels in the
segmentation mask, as in the detector's training labels) and the detector's box, per person
height; docs/find_people.md explains how ``target_height_px`` was chosen from this table.

Usage: python bench/find_people_box_height.py [--weights PATH] [--heights 1.6 1.7 1.8 1.9]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from bench_find_people import PERSON, SCENARIO, default_weights

from app.household import Simulation
from app.robot import decode_segmentation
from app.scenario import Placement, Start, load_scenario
from behaviours.config import load_behaviour_config
from perception.detector import YoloDetector

ROBOT = Placement(x=4.3, y=2.5, yaw=180.0)   # facing the open west half of the room
DISTANCES = (0.8, 0.9, 0.95, 1.0, 1.05, 1.1, 1.2, 1.5, 2.0, 3.0)


def box_heights(height: float, detector: YoloDetector) -> list[tuple[float, int, float | None]]:
    """(distance, label box height, detector box height or None) for a person ``height``
    metres tall facing the robot at each of DISTANCES."""
    base = load_scenario(SCENARIO)
    tom = next(q for q in base.people if q.name == PERSON)
    tom = tom.model_copy(update={"body": tom.body.model_copy(update={"height": height}),
                                 "start": Start(x=1.0, y=ROBOT.y, yaw=0.0), "events": ()})
    scenario = base.model_copy(update={"people": (tom,), "robot": base.robot.model_copy(
        update={"start": ROBOT})})
    pitch = load_behaviour_config().find_people.head_pitch
    rows = []
    with Simulation(scenario) as sim:
        sim.robot.move_joints({"HeadPitch": pitch, "HeadYaw": 0.0}, 1.0)
        for _ in range(20):
            sim.step()
        person = sim.world.people[PERSON]
        for d in DISTANCES:
            person.place(ROBOT.x - d, ROBOT.y, 0.0)
            rgb, seg = sim.robot.camera_frame_with_segmentation()
            rows_px = np.nonzero((decode_segmentation(seg)[0] == person.body_id).any(axis=1))[0]
            boxes = [b for b in detector.detect(rgb) if b.cls == "person"]
            best = max(boxes, key=lambda b: b.height, default=None)
            rows.append((d, int(rows_px.max() - rows_px.min() + 1),
                         None if best is None else round(best.height, 1)))
    return rows


def main() -> None:
    """Print one markdown table row per distance and person height."""
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--weights", type=Path, default=None)
    parser.add_argument("--heights", type=float, nargs="+", default=[1.6, 1.7, 1.8, 1.9])
    args = parser.parse_args()
    weights = args.weights or default_weights()
    detector = YoloDetector(weights)
    print(f"weights: {weights}\n\n| person height (m) | distance (m) | label box (px) | "
          "detector box (px) |\n| --- | --- | --- | --- |")
    for h in args.heights:
        for d, label, found in box_heights(h, detector):
            print(f"| {h} | {d} | {label} | {'-' if found is None else found} |")


if __name__ == "__main__":
    main()
