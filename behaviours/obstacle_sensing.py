"""What the charge skill's planner learns of obstacles off the floor map: the base's laser
scanners at every tick and, when Sense took a head-camera frame this tick, its depth image
(docs/navigation.md). The simulator's people are never looked up."""

from __future__ import annotations

import math

import numpy as np

from behaviours.context import Context
from behaviours.person_range import PersonRange
from robot.navigation import Navigator

Velocity = tuple[float, float, float]


class ObstacleSensing:
    """Feeds ``navigator`` the robot's scans and depth frames, and holds back the base's
    moves near what they sensed."""

    def __init__(self, ctx: Context, navigator: Navigator) -> None:
        self.ctx, self.navigator = ctx, navigator
        self.range = PersonRange(ctx.robot, ctx.config.perception)
        self._frame_t = -np.inf

    @classmethod
    def for_charge(cls, ctx: Context) -> ObstacleSensing:
        """Sensing for a planner on the floor map with the charge skill's settings."""
        cfg = ctx.config.charge
        return cls(ctx, Navigator(ctx.floor_plan, cfg.grid_resolution, cfg.robot_radius,
                                  cfg.obstacle_memory_s, cfg.static_margin_m,
                                  cfg.sensed_clearance_m, cfg.body_radius, cfg.tracks))

    def guard(self, pose: tuple[float, float, float], command: Velocity,
              ) -> tuple[Velocity, bool]:
        """``command`` as the obstacles sensed lately allow, and whether its translation is
        held. Held (the base still turns) while one lies on the side the base would move to
        within ``security_distance_m`` of its shell, or straight in its way
        (``robot_radius`` to either side) within that plus the way covered in
        ``security_time_s`` at the commanded speed. Otherwise the speed falls in proportion
        while the nearest on that side is within ``slow_distance_m`` of the shell, to
        nothing at ``security_distance_m`` (speed and separation)."""
        vx, vy, wz = command
        if (vx, vy) == (0.0, 0.0):
            return command, False
        cfg, memory = self.ctx.config.charge, self.navigator.memory
        near = self.ctx.robot.lasers.cfg.mount_radius_m + cfg.security_distance_m
        heading = pose[2] + math.atan2(vy, vx)
        if memory.ahead(pose[:2], heading, near + math.hypot(vx, vy) * cfg.security_time_s,
                        cfg.robot_radius, near):
            return (0.0, 0.0, wz), True
        gap = memory.nearest_ahead(pose[:2], heading) - near
        share = min(1.0, gap / (cfg.slow_distance_m - cfg.security_distance_m))
        return (vx * share, vy * share, wz), False

    def update(self, now: float, depth: np.ndarray | None, frame_t: float) -> None:
        """A laser scan now, and the depth frame if it was taken now (the camera pose it
        was taken from is the pose now) and not used yet."""
        self.navigator.observe(self.ctx.robot.lasers.scan(), now)
        if depth is not None and frame_t == now and frame_t != self._frame_t:
            self._frame_t = frame_t
            self.navigator.add_points(self.depth_points(depth), now)

    def depth_points(self, depth: np.ndarray) -> np.ndarray:
        """Floor positions ((N, 2) m) of a sparse grid of the frame's pixels whose surface
        lies between ``min_height_m`` and ``max_height_m`` above the floor and within
        ``max_range_m`` of the base (outside the base's own shell)."""
        cfg, robot = self.ctx.config.charge.depth_points, self.ctx.robot
        rows = np.arange(cfg.stride // 2, depth.shape[0], cfg.stride)
        cols = np.arange(cfg.stride // 2, depth.shape[1], cfg.stride)
        z = depth[np.ix_(rows, cols)]
        pos, rays = self.range.rays(depth.shape, cols[None, :] + 0.5, rows[:, None] + 0.5)
        points = pos + z[..., None] * rays
        x, y, _ = robot.base.pose()
        reach = np.hypot(points[..., 0] - x, points[..., 1] - y)
        keep = ((z < robot.camera.cfg.far * 0.99) & (points[..., 2] >= cfg.min_height_m)
                & (points[..., 2] <= cfg.max_height_m) & (reach <= cfg.max_range_m)
                & (reach >= robot.lasers.cfg.mount_radius_m))
        return points[keep][:, :2]
