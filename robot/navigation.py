"""Navigation in a household: an occupancy grid of the floor and shortest paths on it for
the omnidirectional base (docs/navigation.md).

- :class:`OccupancyGrid`: square cells over the rooms; a cell is blocked when its centre lies
  within the robot's radius of an obstacle footprint or of the outside of the house.
- :class:`Planner`: shortest paths (scipy's compiled Dijkstra) on the 8-connected graph of
  a static grid's free cells, start and goal snapped to the nearest free cell, the path
  shortened by line of sight.
- :class:`Navigator`: the static grid of one household layout with the obstacles the robot
  has sensed lately on top (:class:`~robot.sensed_obstacles.ObstacleMemory`).

The path follower that drives the base along a planned path is in
:mod:`robot.path_follower`.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from functools import cached_property, lru_cache
from typing import Protocol

import numpy as np
from scipy import ndimage, sparse
from scipy.sparse import csgraph

from robot.geometry import Footprint, Pose2D
from robot.lasers import Scan
from robot.obstacle_tracks import TracksConfig
from robot.sensed_obstacles import ObstacleMemory

Point = tuple[float, float]
Cell = tuple[int, int]
Bounds = tuple[float, float, float, float]        # x_min, y_min, x_max, y_max


class FloorPlan(Protocol):
    """The robot's map of its household: the rooms' bounds, the footprints and heights of
    what does not move (walls, furniture, floor objects, the dock plate) and the dock."""

    def room_bounds(self) -> dict[str, Bounds]:
        """``(x_min, y_min, x_max, y_max)`` of each room, by name."""
        ...

    def obstacles(self) -> list[Footprint]:
        """The floor footprints of the household's fixed obstacles."""
        ...

    def furniture_top(self, name: str) -> float:
        """How high the furniture ``name`` reaches (m): what a camera can see over."""
        ...

    def dock_pose(self) -> Pose2D:
        """Where the robot stands when docked, facing the dock's marker plate."""
        ...
NEIGHBOURS = ((1, 0), (0, 1), (1, 1), (1, -1))    # each undirected 8-neighbour edge once


def footprint_distance(f: Footprint, xs: np.ndarray, ys: np.ndarray) -> np.ndarray:
    """Distance (m) from each point to the rectangle ``f`` (0 inside it)."""
    c, s = math.cos(f.yaw), math.sin(f.yaw)
    dx, dy = xs - f.x, ys - f.y
    u = np.abs(c * dx + s * dy) - f.half_x
    v = np.abs(-s * dx + c * dy) - f.half_y
    return np.hypot(np.maximum(u, 0.0), np.maximum(v, 0.0))


class OccupancyGrid:
    """Cells of ``resolution`` m; ``blocked[i, j]`` for the cell whose centre is
    ``origin + (i + 0.5, j + 0.5) * resolution`` (i along x, j along y)."""

    def __init__(self, blocked: np.ndarray, origin: Point, resolution: float,
                 radius: float) -> None:
        self.blocked = blocked
        self.origin = origin
        self.resolution = resolution
        self.radius = radius

    @classmethod
    def build(cls, rooms: Iterable[Bounds], obstacles: Iterable[Footprint], resolution: float,
              radius: float) -> OccupancyGrid:
        """The grid over the rooms' bounding box: cells outside every room, or within
        ``radius`` of an obstacle or of the outside, are blocked."""
        rooms = list(rooms)
        x0, y0 = min(r[0] for r in rooms) - resolution, min(r[1] for r in rooms) - resolution
        x1, y1 = max(r[2] for r in rooms) + resolution, max(r[3] for r in rooms) + resolution
        shape = (math.ceil((x1 - x0) / resolution), math.ceil((y1 - y0) / resolution))
        grid = cls(np.zeros(shape, dtype=bool), (x0, y0), resolution, radius)
        xs, ys = grid.centres()
        inside = np.zeros(shape, dtype=bool)
        for rx0, ry0, rx1, ry1 in rooms:
            inside |= (xs >= rx0) & (xs <= rx1) & (ys >= ry0) & (ys <= ry1)
        grid.blocked = ndimage.distance_transform_edt(inside) * resolution <= radius
        return grid.with_obstacles(obstacles)

    def near(self, rooms: Iterable[Bounds], obstacles: Iterable[Footprint],
             margin: float) -> np.ndarray:
        """Cells whose centre lies within ``margin`` of one of ``obstacles``, or outside
        every room shrunk by ``margin``: what a map of these explains."""
        xs, ys = self.centres()
        inside = np.zeros(self.blocked.shape, dtype=bool)
        for x0, y0, x1, y1 in rooms:
            inside |= ((xs >= x0 + margin) & (xs <= x1 - margin) & (ys >= y0 + margin)
                       & (ys <= y1 - margin))
        out = ~inside
        for f in obstacles:
            out |= footprint_distance(f, xs, ys) <= margin
        return out

    def with_obstacles(self, obstacles: Iterable[Footprint]) -> OccupancyGrid:
        """A copy with the cells within ``radius`` of ``obstacles`` blocked too."""
        xs, ys = self.centres()
        blocked = self.blocked.copy()
        for f in obstacles:
            blocked |= footprint_distance(f, xs, ys) <= self.radius
        return OccupancyGrid(blocked, self.origin, self.resolution, self.radius)

    def centres(self) -> tuple[np.ndarray, np.ndarray]:
        """x and y of every cell centre, each shaped like ``blocked``."""
        n, m = self.blocked.shape
        i, j = np.meshgrid(np.arange(n), np.arange(m), indexing="ij")
        res = self.resolution
        return self.origin[0] + (i + 0.5) * res, self.origin[1] + (j + 0.5) * res

    def cell(self, x: float, y: float) -> Cell:
        """The cell holding (x, y), clamped into the grid."""
        n, m = self.blocked.shape
        i = int(np.clip((x - self.origin[0]) // self.resolution, 0, n - 1))
        j = int(np.clip((y - self.origin[1]) // self.resolution, 0, m - 1))
        return i, j

    def centre(self, cell: Cell) -> Point:
        """World coordinates of a cell's centre."""
        return (self.origin[0] + (cell[0] + 0.5) * self.resolution,
                self.origin[1] + (cell[1] + 0.5) * self.resolution)

    def is_free(self, x: float, y: float) -> bool:
        """Whether the cell holding (x, y) is free."""
        return not self.blocked[self.cell(x, y)]

    def nearest(self, cell: Cell, allowed: np.ndarray | None = None) -> Cell:
        """The nearest free cell (among ``allowed`` cells if given) to ``cell``."""
        ok = ~self.blocked if allowed is None else allowed & ~self.blocked
        if ok[cell]:
            return cell
        _, (ii, jj) = ndimage.distance_transform_edt(~ok, return_indices=True)
        return int(ii[cell]), int(jj[cell])

    def visible(self, a: Point, b: Point) -> bool:
        """Whether every cell that the straight segment a-b passes through is free: the
        segment is cut where it crosses grid lines and each piece's midpoint is looked up."""
        pa = (np.asarray(a) - self.origin) / self.resolution     # in cells
        pb = (np.asarray(b) - self.origin) / self.resolution
        cuts = [np.array([0.0, 1.0])]
        for k in (0, 1):
            if pa[k] != pb[k]:
                lines = np.arange(math.ceil(min(pa[k], pb[k])), math.floor(max(pa[k], pb[k])) + 1)
                cuts.append((lines - pa[k]) / (pb[k] - pa[k]))
        t = np.unique(np.concatenate(cuts))
        mids = pa + ((t[:-1] + t[1:]) / 2)[:, None] * (pb - pa)
        cells = np.clip(np.floor(mids).astype(int), 0, np.array(self.blocked.shape) - 1)
        return not self.blocked[cells[:, 0], cells[:, 1]].any()

    def clear_ahead(self, a: Point, b: Point) -> bool:
        """Whether the segment a-b is free beyond ``radius`` of ``a`` (a robot standing close
        to furniture starts inside its inflated footprint) and free from its first free
        point on."""
        steps = max(1, math.ceil(math.dist(a, b) / self.resolution))
        points = [(a[0] + (b[0] - a[0]) * k / steps, a[1] + (b[1] - a[1]) * k / steps)
                  for k in range(steps + 1)]
        first = next((k for k, q in enumerate(points)
                      if self.is_free(*q) or math.dist(a, q) > self.radius), len(points))
        return all(self.is_free(*q) for q in points[first:])


def grid_graph(free: np.ndarray, resolution: float) -> sparse.csr_matrix:
    """8-connected graph of the free cells as a sparse adjacency matrix over all cells (flat
    index ``i * columns + j``; blocked cells have no edges); edges weigh their length in
    metres, and a diagonal step needs both cells beside it free (no cutting a blocked
    corner). Each edge is stored both ways."""
    i, j = np.nonzero(free)
    n, m = free.shape
    rows, cols, weights = [], [], []
    for di, dj in NEIGHBOURS:
        i2, j2 = i + di, j + dj
        ok = (i2 < n) & (j2 >= 0) & (j2 < m)
        i1, j1, i2, j2 = i[ok], j[ok], i2[ok], j2[ok]
        ok = free[i2, j2] & free[i2, j1] & free[i1, j2]
        a, b = i1[ok] * m + j1[ok], i2[ok] * m + j2[ok]
        rows += [a, b]
        cols += [b, a]
        weights.append(np.full(2 * len(a), resolution * math.hypot(di, dj)))
    return sparse.csr_matrix((np.concatenate(weights), (np.concatenate(rows),
                                                        np.concatenate(cols))),
                             shape=(n * m, n * m))


def shortcut(grid: OccupancyGrid, points: Sequence[Point]) -> list[Point]:
    """Drop every point that the one before it can see past: from each kept point, jump to
    the last point of the run that stays in line of sight."""
    out, i = [points[0]], 0
    while i < len(points) - 1:
        j = i + 1
        while j + 1 < len(points) and grid.visible(points[i], points[j + 1]):
            j += 1
        out.append(points[j])
        i = j
    return out


class Planner:
    """Shortest paths on a static grid; ``plan`` may block more cells (people) on top. With
    a ``body`` grid (the map's obstacles grown by the base's radius only), a robot standing
    inside the static grid's inflation first slides out the shortest way its base fits."""

    def __init__(self, grid: OccupancyGrid, body: OccupancyGrid | None = None) -> None:
        self.grid = grid
        self.body = body   # the map's obstacles grown by the base's own radius only

    @cached_property
    def graph(self) -> sparse.csr_matrix:
        """The free cells of the static grid as a graph (built on first use)."""
        return grid_graph(~self.grid.blocked, self.grid.resolution)

    @cached_property
    def body_graph(self) -> sparse.csr_matrix:
        """The cells of the ``body`` grid where the base fits, as a graph."""
        return grid_graph(~self.body.blocked, self.body.resolution)

    def _slide(self, grid: OccupancyGrid, start: Point, allowed: np.ndarray,
               ) -> list[Point] | None:
        """A way from ``start``, inside ``grid``'s inflation, to the nearest ``allowed``
        free cell of ``grid`` through cells where the base fits (``body``): the points to
        slide through, ending at that cell's centre; None without a ``body`` or a way."""
        if self.body is None:
            return None
        columns = grid.blocked.shape[1]
        first = self.body.nearest(self.body.cell(*start))
        lengths, previous = csgraph.dijkstra(self.body_graph, indices=first[0] * columns
                                             + first[1], return_predecessors=True)
        lengths = np.where((allowed & ~grid.blocked).ravel(), lengths, np.inf)
        at = int(np.argmin(lengths))
        if not np.isfinite(lengths[at]):
            return None
        cells = []
        while at >= 0:
            cells.append(divmod(at, columns))
            at = int(previous[at])
        return shortcut(self.body, [start, *(grid.centre(c) for c in reversed(cells))])[1:]

    def plan(self, start: Point, goal: Point, grid: OccupancyGrid | None = None,
             ) -> list[Point] | None:
        """Waypoints from ``start`` to ``goal`` avoiding the blocked cells of ``grid`` (the
        static grid, or one made from it with :meth:`OccupancyGrid.with_obstacles`), or
        None when there is no way. The goal is snapped to the nearest free cell, the start
        to the nearest free cell that connects to it (with a ``body`` grid, the nearest the
        base can slide to, and the waypoints begin with the points of that slide, all in
        blocked cells but the last); the first waypoint is ``start`` itself unless it had to
        be snapped, the last is ``goal`` unless it had to be snapped."""
        grid = grid or self.grid
        goal_cell = grid.nearest(grid.cell(*goal))
        # the free cells that connect to the goal: a diagonal step needs both cells beside
        # it free (grid_graph), so these are the goal's 4-connected component
        labels, _ = ndimage.label(~grid.blocked)
        reachable = labels == labels[goal_cell]
        start_cell = grid.nearest(grid.cell(*start), reachable)
        slide = (self._slide(grid, start, reachable) or []) if start_cell != grid.cell(*start) \
            else []
        if slide:
            start_cell = grid.cell(*slide[-1])
        if not reachable[start_cell]:
            return None
        graph = self.graph
        extra = (grid.blocked & ~self.grid.blocked).ravel()
        if extra.any():   # the same graph without the edges of the newly blocked cells
            keep = sparse.diags((~extra).astype(float))
            graph = keep @ graph @ keep
        columns = grid.blocked.shape[1]
        flat = start_cell[0] * columns + start_cell[1]
        _, previous = csgraph.dijkstra(graph, indices=flat, return_predecessors=True)
        cells, at = [], goal_cell[0] * columns + goal_cell[1]
        while at >= 0:
            cells.append(divmod(int(at), columns))
            at = previous[at]
        points = [grid.centre(c) for c in reversed(cells)]
        if grid.cell(*start) == start_cell:
            points[0] = start
        if grid.cell(*goal) == goal_cell:
            points[-1] = goal
        return slide[:-1] + shortcut(grid, points)

    def nearest_goal(self, start: Point, goals: Sequence[Point],
                     extra: Sequence[float] | None = None) -> Point | None:
        """Of ``goals`` in free cells of the static grid, the one with the least path length
        from ``start`` (snapped to its nearest free cell) plus its ``extra`` cost (m), or
        None when none is reachable."""
        grid = self.grid
        columns = grid.blocked.shape[1]
        first = grid.nearest(grid.cell(*start))
        lengths = csgraph.dijkstra(self.graph, indices=first[0] * columns + first[1])
        costs = []
        for goal, more in zip(goals, extra or [0.0] * len(goals), strict=True):
            i, j = grid.cell(*goal)
            if np.isfinite(length := lengths[i * columns + j]):   # free and reachable
                costs.append((length + more, goal))
        return min(costs)[1] if costs else None


@lru_cache(maxsize=8)
def _static_planner(rooms: tuple[Bounds, ...], obstacles: tuple[Footprint, ...],
                    resolution: float, radius: float, body: float | None = None) -> Planner:
    return Planner(OccupancyGrid.build(rooms, obstacles, resolution, radius),
                   None if body is None else OccupancyGrid.build(rooms, obstacles, resolution,
                                                                 body))


@lru_cache(maxsize=8)
def _explained(rooms: tuple[Bounds, ...], obstacles: tuple[Footprint, ...], resolution: float,
               radius: float, margin: float) -> np.ndarray:
    return _static_planner(rooms, obstacles, resolution, radius).grid.near(rooms, obstacles,
                                                                            margin)


class Navigator:
    """Plans on one floor plan: the static grid (the floor map) and its graph are shared by every
    navigator of the same household layout (``body``: the base's radius, for sliding out of
    the inflation, :class:`Planner`); the obstacles its sensors reported lately
    (:meth:`observe`, :meth:`add_points`) are avoided too, with ``clearance`` m more room
    than the map's (they may be people: arms swing wider than the legs the scanners see).
    The simulator's people are never looked up: the robot avoids them only once it has
    sensed them."""

    def __init__(self, floor: FloorPlan, resolution: float, radius: float, memory_s: float = 0.0,
                 static_margin: float = 0.05, clearance: float = 0.0,
                 body: float | None = None, tracks: TracksConfig | None = None) -> None:
        self.clearance = clearance
        rooms, static = tuple(floor.room_bounds().values()), tuple(floor.obstacles())
        self.planner = _static_planner(rooms, static, resolution, radius, body)
        grid = self.planner.grid
        self.memory = ObstacleMemory(_explained(rooms, static, resolution, radius, static_margin),
                                     grid.origin, resolution, memory_s, tracks)

    def observe(self, scan: Scan, now: float) -> None:
        """A laser scan at ``now``: its rays clear the cells they passed, its hits mark theirs."""
        self.memory.observe(scan, now)

    def add_points(self, points: np.ndarray, now: float) -> None:
        """Surface points ((N, 2) m on the floor) another sensor saw at ``now``."""
        self.memory.add(points, now)

    def sensed_grid(self) -> OccupancyGrid:
        """Only the cells near obstacles sensed lately blocked (not the map's)."""
        static = self.planner.grid
        return OccupancyGrid(self.memory.blocked(static.radius + self.clearance), static.origin,
                             static.resolution, static.radius)

    def grid(self) -> OccupancyGrid:
        """The static grid with the cells near obstacles sensed lately blocked too."""
        sensed = self.sensed_grid()
        sensed.blocked |= self.planner.grid.blocked
        return sensed

    def plan(self, start: Point, goal: Point) -> list[Point] | None:
        """Waypoints from ``start`` to ``goal`` around the map's and the sensed obstacles,
        or None."""
        return self.planner.plan(start, goal, self.grid())
