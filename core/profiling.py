"""Where a run's wall time goes: ``companion run --profile``.

A :class:`Profile` times chosen methods of the objects a run is built from (the
simulation's step, the camera's render, the detector, the dialogue, the writers), each under
a named part. Time is counted once: a timed call inside another (the detector inside the
tree's tick) is taken out of the outer part, so the parts add up to the time measured.
Nothing is timed unless a run asks for it; an instrumented method costs two clock reads.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from functools import wraps
from typing import Any


class Profile:
    """Exclusive wall time and call counts per part."""

    def __init__(self) -> None:
        self.seconds: dict[str, float] = {}
        self.calls: dict[str, int] = {}
        self._inner: list[float] = []   # per open timed call: time spent in timed calls inside

    def timed(self, fn: Callable[..., Any], part: str) -> Callable[..., Any]:
        """``fn`` with its calls counted under ``part``."""
        self.seconds.setdefault(part, 0.0)
        self.calls.setdefault(part, 0)

        @wraps(fn)
        def call(*args: Any, **kwargs: Any) -> Any:
            self._inner.append(0.0)
            start = time.perf_counter()
            try:
                return fn(*args, **kwargs)
            finally:
                elapsed = time.perf_counter() - start
                inner = self._inner.pop()
                self.seconds[part] += elapsed - inner
                self.calls[part] += 1
                if self._inner:
                    self._inner[-1] += elapsed

        return call

    def add(self, part: str, seconds: float) -> None:
        """Count ``seconds`` spent outside any timed call under ``part``."""
        self.seconds[part] = self.seconds.get(part, 0.0) + seconds
        self.calls[part] = self.calls.get(part, 0) + 1

    def wrap(self, obj: Any, method: str, part: str) -> None:
        """Time ``obj.method`` (this object only) under ``part``; nothing when ``obj`` is
        None."""
        if obj is not None:
            setattr(obj, method, self.timed(getattr(obj, method), part))

    def report(self, wall_s: float) -> dict[str, Any]:
        """Seconds, share of ``wall_s`` and calls per part, largest first, with the rest of
        ``wall_s`` as ``other``."""
        other = max(0.0, wall_s - sum(self.seconds.values()))
        rows = sorted([*self.seconds.items(), ("other", other)], key=lambda kv: -kv[1])
        return {"wall_s": round(wall_s, 2),
                "parts": {part: {"seconds": round(s, 2),
                                 "share": round(s / wall_s, 4) if wall_s > 0 else 0.0,
                                 "calls": self.calls.get(part, 0)} for part, s in rows}}


def profile_table(report: dict[str, Any]) -> str:
    """A Markdown table of :meth:`Profile.report`."""
    lines = ["| part | seconds | share | calls | ms per call |", "|---|---:|---:|---:|---:|"]
    for part, row in report["parts"].items():
        per_call = f"{1000 * row['seconds'] / row['calls']:.2f}" if row["calls"] else ""
        lines.append(f"| {part} | {row['seconds']:.1f} | {100 * row['share']:.1f} % | "
                     f"{row['calls']} | {per_call} |")
    lines.append(f"| **total** | {report['wall_s']:.1f} | 100 % | | |")
    return "\n".join(lines)
