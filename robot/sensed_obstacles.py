"""Obstacles the robot senses that its floor map does not hold: people, a dropped box.

The floor map (walls, furniture, floor objects, the dock's plate) is known beforehand, like
a map a home robot builds on its first run. Everything else the planner avoids comes from
the sensors: points where a laser ray or a depth-camera pixel met a surface that the map
does not explain (farther than ``static_margin`` from every mapped footprint) mark their
grid cell as seen *now*. A cell stays an obstacle for ``memory_s`` after it was last seen,
or until a laser ray passes through it to something farther (the cell was seen free). The
planner inflates these cells by the robot's radius like the map's obstacles. What the
scanners see off the map is also tracked (:mod:`robot.obstacle_tracks`): while a track is
out of every ray's reach, the cells round where it is expected count as occupied too
(docs/navigation.md).
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage

from robot.lasers import Scan
from robot.obstacle_tracks import ObstacleTracks, TracksConfig


class ObstacleMemory:
    """Grid cells where sensors met something the map does not explain, with when, and
    (given ``tracks``) the cells round tracked things the scanners cannot see now."""

    def __init__(self, explained: np.ndarray, origin: tuple[float, float], resolution: float,
                 memory_s: float, tracks: TracksConfig | None = None) -> None:
        self.explained = explained
        self.origin = np.asarray(origin, dtype=float)
        self.resolution = resolution
        self.memory_s = memory_s
        self.seen = np.full(explained.shape, -np.inf)   # when each cell was last seen occupied
        self.now = -np.inf
        self.tracks = ObstacleTracks(tracks) if tracks is not None else None
        self.expected = np.zeros(explained.shape, dtype=bool)   # round unseen tracks, now
        self.free = np.zeros(explained.shape, dtype=bool)       # the last scan's rays passed

    def _in_grid(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Those of ``points`` ((N, 2) m) inside the grid, and their cells' indices."""
        points = np.asarray(points, dtype=float).reshape(-1, 2)
        ij = np.floor((points - self.origin) / self.resolution).astype(int)
        ok = ((ij >= 0) & (ij < np.array(self.seen.shape))).all(axis=1)
        return points[ok], ij[ok]

    def _cells(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Indices of the cells holding ``points`` ((N, 2) m), those inside the grid only."""
        _, ij = self._in_grid(points)
        return ij[:, 0], ij[:, 1]

    def _off_map(self, points: np.ndarray) -> np.ndarray:
        """Those of ``points`` ((N, 2) m) inside the grid whose cells the map does not
        explain."""
        points, ij = self._in_grid(points)
        return points[~self.explained[ij[:, 0], ij[:, 1]]]

    def add(self, points: np.ndarray, now: float) -> None:
        """Points ((N, 2) m) where a sensor met a surface at time ``now``."""
        self.now = max(self.now, now)
        self.seen[self._cells(self._off_map(points))] = now

    def clear(self, scan: Scan, now: float) -> None:
        """Forget the cells the rays of ``scan`` passed through: from each ray's start to a
        cell short of where it ended."""
        self.now = max(self.now, now)
        step = self.resolution / 2
        self.free = np.zeros(self.seen.shape, dtype=bool)
        for origin, end in zip(scan.origins, scan.ends, strict=True):
            length = float(np.hypot(*(end - origin))) - self.resolution
            if length <= 0:
                continue
            t = np.arange(0.0, length, step)[:, None] / (length + self.resolution)
            self.free[self._cells(origin + t * (end - origin))] = True
        self.seen[self.free] = -np.inf

    def observe(self, scan: Scan, now: float) -> None:
        """A laser scan: free space along its rays first, then its hits, then where the
        tracked things it did not find are expected (where its rays did not pass)."""
        self.clear(scan, now)
        self.add(scan.points, now)
        if self.tracks is not None:
            self._expect(scan, now)

    def _expect(self, scan: Scan, now: float) -> None:
        """Follow the tracks with the scan's off-map hits; the cells round each track no hit
        continued, where the scan did not see (its rays' cells and their neighbours), are
        expected occupied; a track with none left is forgotten."""
        unseen = ~ndimage.binary_dilation(self.free) & ~self.explained
        self.expected = np.zeros(self.seen.shape, dtype=bool)
        for track in self.tracks.update(self._off_map(scan.points), now):
            disc = self._disc(track.at(now), self.tracks.cfg.radius_m) & unseen
            if disc.any():
                self.expected |= disc
            else:
                self.tracks.forget(track)

    def _disc(self, centre: np.ndarray, radius: float) -> np.ndarray:
        """The cells whose centres lie within ``radius`` of ``centre``."""
        mask = np.zeros(self.seen.shape, dtype=bool)
        shape = np.array(mask.shape)
        lo = np.clip(np.floor((centre - radius - self.origin) / self.resolution), 0, shape)
        hi = np.clip(np.ceil((centre + radius - self.origin) / self.resolution), 0, shape)
        (i0, j0), (i1, j1) = lo.astype(int), hi.astype(int)
        i, j = np.ogrid[i0:i1, j0:j1]
        x = self.origin[0] + (i + 0.5) * self.resolution - centre[0]
        y = self.origin[1] + (j + 0.5) * self.resolution - centre[1]
        mask[i0:i1, j0:j1] = x ** 2 + y ** 2 <= radius ** 2
        return mask

    def active(self) -> np.ndarray:
        """The cells seen occupied within the last ``memory_s`` seconds, and those round
        where the tracked things out of sight are expected now."""
        return (np.isfinite(self.seen) & (self.seen >= self.now - self.memory_s)) | self.expected

    def _offsets(self, position: tuple[float, float]) -> tuple[np.ndarray, np.ndarray]:
        """x and y (m) of the active cells' centres relative to ``position``."""
        i, j = np.nonzero(self.active())
        return (self.origin[0] + (i + 0.5) * self.resolution - position[0],
                self.origin[1] + (j + 0.5) * self.resolution - position[1])

    def ahead(self, position: tuple[float, float], heading: float, reach: float,
              half_width: float, near: float) -> bool:
        """Whether an active cell's centre lies ahead of ``position`` towards ``heading``
        (rad): in the rectangle ``reach`` m long and ``half_width`` m to either side, or in
        the half disc of radius ``near`` on that side."""
        dx, dy = self._offsets(position)
        c, s = np.cos(heading), np.sin(heading)
        along, side = c * dx + s * dy, -s * dx + c * dy
        inside = ((along <= reach) & (np.abs(side) <= half_width)) | (np.hypot(dx, dy) <= near)
        return bool((inside & (along >= 0)).any())

    def nearest_ahead(self, position: tuple[float, float], heading: float) -> float:
        """Distance (m) from ``position`` to the nearest active cell's centre on the side
        of ``heading`` (rad): the half plane a move that way comes nearer to; inf if none."""
        dx, dy = self._offsets(position)
        ahead = np.cos(heading) * dx + np.sin(heading) * dy >= 0
        return float(np.hypot(dx, dy)[ahead].min()) if ahead.any() else np.inf

    def blocked(self, radius: float) -> np.ndarray:
        """The cells within ``radius`` of an active cell (centre to centre)."""
        active = self.active()
        if not active.any():
            return active
        return ndimage.distance_transform_edt(~active) * self.resolution <= radius
