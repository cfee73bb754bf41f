"""The find-people face check on a rendered test split: for every labelled person box at
least ``--min-height`` px tall (close people, as when the robot stands 1 m from someone),
does the detector put a face box of at least conf T in the upper part of that person box?
Reported per threshold for people whose face is labelled there (found) and for people
turned away (passed, which would greet someone from behind).

The check is `behaviours.skills.box_steering.has_face` with the `find_people` region of
`config/behaviour.yaml`, run on the labelled person box so that person-box misses
do not count against it.

Usage: python bench/bench_face_check.py --data runs/detector-data-v2 [--weights PATH]
                                        [--min-height 120] [--json]
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np
from PIL import Image

from behaviours.config import load_behaviour_config
from behaviours.skills.box_steering import has_face
from perception.detector.training.data import CLASSES, Box
from perception.detector.yolo import Detection, YoloDetector

THRESHOLDS = (0.3, 0.4, 0.5, 0.6)


def labelled_boxes(label_file: Path, width: int, height: int) -> list[Detection]:
    """The YOLO label rows of one frame as detections of conf 1."""
    boxes = [Box.from_yolo(line, width, height)
             for line in label_file.read_text().splitlines() if line.strip()]
    return [Detection(CLASSES[b.cls], 1.0, (b.x0, b.y0, b.x1 + 1, b.y1 + 1)) for b in boxes]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", type=Path, required=True, help="data set folder")
    parser.add_argument("--weights", type=Path, default=None,
                        help="YOLO weights (default: the shipped detector)")
    parser.add_argument("--min-height", type=float, default=120.0,
                        help="person boxes at least this tall (px) are scored")
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    args = parser.parse_args()
    region = load_behaviour_config().find_people.face.region
    detector = YoloDetector(args.weights, conf=min(THRESHOLDS))
    faced, turned = [], []  # per person: the detections of their frame
    for image in sorted((args.data / "images" / "test").glob("*.png")):
        frame = np.asarray(Image.open(image).convert("RGB"))
        truth = labelled_boxes(args.data / "labels" / "test" / f"{image.stem}.txt",
                               frame.shape[1], frame.shape[0])
        people = [b for b in truth if b.cls == "person" and b.height >= args.min_height]
        if not people:
            continue
        found = detector.detect(frame)
        for person in people:
            labelled = has_face(person, truth, region, 1.0)
            (faced if labelled else turned).append((person, found))
    rows = {str(t): {"face_found": float(np.mean([has_face(p, f, region, t) for p, f in faced])),
                     "turned_away_passed": float(np.mean([has_face(p, f, region, t)
                                                          for p, f in turned]))}
            for t in THRESHOLDS}
    summary = {"weights": str(detector.path), "data": str(args.data),
               "min_height_px": args.min_height, "people_with_face": len(faced),
               "people_turned_away": len(turned), "by_threshold": rows}
    if args.json:
        print(json.dumps(summary))
        return
    print(f"{len(faced)} close people with their face in view, {len(turned)} turned away")
    print("conf  face found  turned away passed")
    for t, r in rows.items():
        print(f"{t:>4}  {r['face_found']:10.3f}  {r['turned_away_passed']:19.3f}")


if __name__ == "__main__":
    main()
