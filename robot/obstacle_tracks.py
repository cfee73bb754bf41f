"""Tracks of the things the base's laser scanners see off the floor map, followed through
the places the scanners cannot see.

Pepper's three scanner fans leave gaps between them (30-60 degrees either side of the
front, and behind), and see nothing nearer than a little beyond the base's shell. A person
walking round the robot leaves a fan for a gap; the rays then pass where they stood and
see it free, so a memory of cells alone forgets them exactly when they come closest. Each
scan's off-map hits are therefore grouped into objects (points within ``cluster_m`` of
each other: a person's two legs), matched to the tracks of the last scans (the nearest
within ``gate_m`` of where each track was expected), and every track keeps a velocity
estimate. A track no ray finds is expected where its velocity takes it, for ``hold_s``
(the standard way a laser tracker keeps people through occlusions), or for the longer
``still_hold_s`` when it was standing still: a person who stood behind the robot is still
there after the memory of the cells has lapsed. The obstacle memory
takes the part of a disc round that place which the last scan did not see as occupied,
and forgets the track once it saw all of it (docs/navigation.md).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from pydantic import Field, NonNegativeFloat, PositiveFloat
from scipy.cluster.hierarchy import fclusterdata
from scipy.optimize import linear_sum_assignment

from core.config_files import StrictModel


class TracksConfig(StrictModel):
    """How scanner hits become tracked objects, and how long an unseen one is kept."""

    cluster_m: PositiveFloat      # hits closer than this to each other are one object
    gate_m: PositiveFloat         # an object this near where a track was expected continues it
    max_speed: PositiveFloat      # m/s: no track is believed to move faster
    smoothing: float = Field(gt=0.0, le=1.0)   # share of each new velocity estimate
    hold_s: NonNegativeFloat      # s an unseen moving track is kept where it is expected
    still_speed: NonNegativeFloat  # m/s: a track no faster than this is standing still ...
    still_hold_s: NonNegativeFloat  # ... and kept this long unseen (people stay where they stood)
    radius_m: PositiveFloat       # the disc round an unseen track's expected centre: occupied


@dataclass
class Track:
    """An object last seen centred at ``position`` at time ``seen``, moving at ``velocity``."""

    position: np.ndarray
    velocity: np.ndarray
    seen: float

    def at(self, t: float) -> np.ndarray:
        """Where the track is expected at time ``t`` (constant velocity since last seen)."""
        return self.position + self.velocity * (t - self.seen)


def clusters(points: np.ndarray, within: float) -> np.ndarray:
    """The centres ((K, 2) m) of the groups of ``points`` chained within ``within`` of each
    other (single linkage)."""
    if len(points) == 0:
        return np.zeros((0, 2))
    if len(points) == 1:
        return points.reshape(1, 2)
    labels = fclusterdata(points, within, criterion="distance", method="single")
    return np.array([points[labels == k].mean(axis=0) for k in np.unique(labels)])


class ObstacleTracks:
    """The objects the scanners have seen lately, followed from scan to scan."""

    def __init__(self, cfg: TracksConfig) -> None:
        self.cfg = cfg
        self.tracks: list[Track] = []

    def update(self, points: np.ndarray, now: float) -> list[Track]:
        """Follow the objects whose off-map hits at ``now`` are ``points`` ((N, 2) m); return
        the tracks no hit continued now, seen within the last ``hold_s``."""
        cfg = self.cfg
        found = clusters(points, cfg.cluster_m)
        expected = np.array([t.at(now) for t in self.tracks]).reshape(-1, 2)
        followed, taken = [], set()
        if len(expected) and len(found):
            cost = np.linalg.norm(expected[:, None, :] - found[None, :, :], axis=2)
            for k, c in zip(*linear_sum_assignment(cost), strict=True):
                if cost[k, c] <= cfg.gate_m:
                    self._follow(self.tracks[k], found[c], now)
                    followed.append(int(k))
                    taken.add(int(c))
        unseen = [t for k, t in enumerate(self.tracks)
                  if k not in followed and now - t.seen <= self._hold(t)]
        new = [Track(found[c], np.zeros(2), now) for c in range(len(found)) if c not in taken]
        self.tracks = [self.tracks[k] for k in followed] + unseen + new
        return unseen

    def _hold(self, track: Track) -> float:
        """How long ``track`` is kept unseen: longer when it stood still, since where it is
        then stays certain."""
        still = float(np.hypot(*track.velocity)) <= self.cfg.still_speed
        return self.cfg.still_hold_s if still else self.cfg.hold_s

    def forget(self, track: Track) -> None:
        """Drop ``track`` (everywhere it could be has been seen free)."""
        self.tracks = [t for t in self.tracks if t is not track]

    def _follow(self, track: Track, centre: np.ndarray, now: float) -> None:
        """``track`` found again centred at ``centre`` at ``now``."""
        dt = now - track.seen
        if dt > 0:
            step = (centre - track.position) / dt
            velocity = (1 - self.cfg.smoothing) * track.velocity + self.cfg.smoothing * step
            speed = float(np.hypot(*velocity))
            if speed > self.cfg.max_speed:
                velocity *= self.cfg.max_speed / speed
            track.velocity = velocity
        track.position, track.seen = centre, now
