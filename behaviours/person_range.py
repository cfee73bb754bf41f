"""Where the person in a detector box is: range and plausibility from the head camera's
depth image and the robot's own kinematics. Shared by Sense (the human-present stimulus)
and the find-people leaves (the approach); docs/find_people.md explains the geometry."""

from __future__ import annotations

import math

import numpy as np

from behaviours.config import PerceptionConfig
from perception.detector.yolo import Detection
from robot.body import Body


class PersonRange:
    """Distance and plausibility of person boxes in depth frames of ``robot``'s camera."""

    def __init__(self, robot: Body, cfg: PerceptionConfig) -> None:
        self.robot, self.cfg = robot, cfg
        self.tan_half_vfov = math.tan(math.radians(robot.camera.cfg.fov_deg) / 2)

    def distance(self, depth: np.ndarray, box: Detection) -> float | None:
        """Floor distance (m) from the base to the nearest surface of the person in ``box``:
        the ``depth_percentile`` of the floor distances of the pixels in the box's torso
        window (``depth_window``: a middle share of its columns, a band of its rows below the
        head; background seen past the body lies farther and drops out). None without
        valid depth there."""
        rows, cols = depth.shape
        x0, y0, x1, y1 = box.box
        share, (top, bottom) = self.cfg.depth_window
        half = share * (x1 - x0) / 2
        c0, c1 = int(max(0, box.centre[0] - half)), int(min(cols, box.centre[0] + half + 1))
        r0, r1 = int(max(0, y0 + top * (y1 - y0))), int(min(rows, y0 + bottom * (y1 - y0) + 1))
        z = depth[r0:r1, c0:c1]
        valid = z < self.robot.camera.cfg.far * 0.99
        if not valid.any():
            return None
        pos, rays = self.rays(depth.shape, np.arange(c0, c1)[None, :] + 0.5,
                              np.arange(r0, r1)[:, None] + 0.5)
        points = pos[:2] + z[..., None] * rays[..., :2]
        base = np.asarray(self.robot.base.pose()[:2])
        return float(np.percentile(np.linalg.norm(points - base, axis=-1)[valid],
                                   self.cfg.depth_percentile))

    def plausible(self, depth: np.ndarray, box: Detection, reach: float | None) -> bool:
        """Whether the box can hold a person: the top edge's ray, at the box's distance
        ``reach`` (from :meth:`distance`), stays below ``person_max_height_m``. A false
        positive on a wall or a cupboard fills the frame's height from farther away than any
        person could. A box cut off by the frame's top, or without depth, passes."""
        if reach is None or box.box[1] <= 1:
            return True
        pos, ray = self.rays(depth.shape, np.asarray(box.centre[0]), np.asarray(box.box[1]))
        top = pos[2] + reach * ray[2] / math.hypot(ray[0], ray[1])
        return top <= self.cfg.person_max_height_m

    def rays(self, shape: tuple[int, ...], col: np.ndarray,
             row: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The camera position and the viewing rays (last axis x, y, z in the world; unit
        length along the optical axis) through image points (``col``, ``row`` in pixels,
        broadcast together) of a frame of ``shape``."""
        pos, axis, up = self.robot.camera.pose()
        rows, cols = shape[:2]
        focal = rows / 2 / self.tan_half_vfov
        u, v = (col - cols / 2) / focal, (rows / 2 - row) / focal
        return pos, axis + u[..., None] * np.cross(axis, up) + v[..., None] * up
