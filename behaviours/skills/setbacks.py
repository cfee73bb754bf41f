"""What the find-people approach keeps after its setbacks (docs/find_people.md): the way out
when the base reports being blocked on the way to a person (back up, then step sideways,
keeping the side that got through for the next time), and the places it gave up on.
"""

from __future__ import annotations

import math

from behaviours.config import FindPeopleConfig


class Escape:
    """Backs up for ``escape_back_s``, then steps sideways for ``escape_side_s``, both at
    ``escape_speed``; left first."""

    def __init__(self, cfg: FindPeopleConfig) -> None:
        self.cfg = cfg
        self.side = 1.0
        self.start = -math.inf   # s: when the escape under way began

    def reset(self) -> None:
        """No escape under way; the next one steps to the left."""
        self.side, self.start = 1.0, -math.inf

    def begin(self, now: float) -> None:
        """Start an escape at ``now``."""
        self.start = now

    def command(self, now: float, blocked: bool, vx: float, wz: float,
                ) -> tuple[float, float, float]:
        """The (vx, vy, wz) command: the controllers' own, or an escape after the base
        reported being ``blocked`` while driving forwards. A blocked sidestep starts a new
        escape to the other side."""
        cfg = self.cfg
        sidestep_from = self.start + cfg.escape.back_s
        if now >= sidestep_from + cfg.escape.side_s:
            if not (blocked and vx > 0):
                return vx, 0.0, wz
            self.start = now
        elif blocked and now > sidestep_from:
            self.side = -self.side
            self.start = now
        if now < self.start + cfg.escape.back_s:
            return -cfg.escape.speed, 0.0, 0.0
        return 0.0, self.side * cfg.escape.speed, 0.0


class Ignored:
    """Where the robot gave up on a person (each floor spot ignored for ``ignore_s``), and
    the world headings in which a near box without a face vanished, and how often."""

    def __init__(self, cfg: FindPeopleConfig) -> None:
        self.cfg = cfg
        self.until: dict[tuple[float, float], float] = {}   # spot -> ignored until (s)
        self.vanished: dict[float, int] = {}   # world heading (rad) -> near box lost, times

    def clear(self) -> None:
        """Nothing ignored, nothing vanished."""
        self.until, self.vanished = {}, {}

    def expire(self, now: float) -> None:
        """Forget the spots whose time is up at ``now``."""
        self.until = {s: t for s, t in self.until.items() if t > now}

    def add(self, spot: tuple[float, float], now: float) -> None:
        """Ignore ``spot`` from ``now`` for ``ignore_s``."""
        self.until[spot] = now + self.cfg.give_up.ignore_s

    def spots(self) -> list[tuple[float, float]]:
        """The spots ignored now."""
        return list(self.until)

    def headings_from(self, x: float, y: float) -> tuple[float, ...]:
        """The world headings from ``(x, y)`` to the spots ignored now."""
        return tuple(math.atan2(sy - y, sx - x) for sx, sy in self.until)

    def vanished_at(self, heading: float) -> int | None:
        """Count a near box lost at world ``heading`` (one within ``ignore_width_deg`` of an
        earlier one counts with it); the count once it reaches ``vanish_strikes`` (and
        forgotten then), else None."""
        width = math.radians(self.cfg.give_up.ignore_width_deg)
        key = next((h for h in self.vanished
                    if abs(math.remainder(h - heading, math.tau)) <= width), heading)
        count = self.vanished.pop(key, 0) + 1
        if count < self.cfg.give_up.vanish_strikes:
            self.vanished[heading] = count
            return None
        return count
