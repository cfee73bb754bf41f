"""The sing/dance routines file (``config/dances.yaml``, docs/skills_body.md): schema
and loader. A routine is a song's title (and other names people use for it), its length,
the lyric lines with the time each one is sung and keyframes of joint targets by Pepper
joint name. The routines are the songs the robot knows: the music answers of the dialogue
offer them (:func:`song_names`)."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Self

from pydantic import Field, NonNegativeFloat, PositiveFloat, create_model, model_validator

from core.config_files import ConfigError, StrictModel, read_yaml, validate
from core.paths import DEFAULTS_DIR
from robot.joints import JOINT_NAMES
from robot.speaker import speech_seconds

DEFAULT_DANCES = DEFAULTS_DIR / "dances.yaml"

# One optional angle (rad) per joint: a misspelt joint is reported as an unknown key.
JointTargets = create_model(
    "JointTargets", __base__=StrictModel, __doc__="Joint targets (rad) by joint name.",
    **{name: (float | None, None) for name in JOINT_NAMES})


class LyricLine(StrictModel):
    """A line sung (said) ``at`` seconds into the routine."""

    at: NonNegativeFloat
    text: str = Field(min_length=1)


class Keyframe(StrictModel):
    """At ``at`` seconds into the routine, start moving the named joints to their targets."""

    at: NonNegativeFloat
    joints: JointTargets

    def targets(self) -> dict[str, float]:
        """The joint targets given in the file (rad)."""
        return self.joints.model_dump(exclude_none=True)

    @model_validator(mode="after")
    def _some_joint(self) -> Self:
        if not self.targets():
            raise ValueError("a keyframe needs at least one joint target")
        return self


class Routine(StrictModel):
    """One song and dance, looped every ``length_s`` seconds."""

    title: str = Field(min_length=1)
    aliases: tuple[str, ...] = ()   # other names people ask for it by ("twinkle twinkle")
    length_s: PositiveFloat
    lyrics: list[LyricLine] = Field(min_length=1)
    keyframes: list[Keyframe] = Field(min_length=1)

    @model_validator(mode="after")
    def _timing(self) -> Self:
        for kind, items in (("lyrics", self.lyrics), ("keyframes", self.keyframes)):
            times = [item.at for item in items]
            if times != sorted(times) or times[-1] >= self.length_s:
                raise ValueError(f"{kind}: times must ascend and stay below length_s")
        ends = [line.at + speech_seconds(line.text) for line in self.lyrics]
        starts = [line.at for line in self.lyrics[1:]] + [self.length_s]
        for i, (end, start) in enumerate(zip(ends, starts, strict=True)):
            if end > start + 1e-9:
                raise ValueError(f"lyrics[{i}] takes until {end:.1f} s to say, past {start:g} s")
        return self


class DanceBook(StrictModel):
    """Schema of the routines file."""

    routines: list[Routine] = Field(min_length=1)


def load_dances(path: str | Path, limits: Mapping[str, tuple[float, float]]) -> DanceBook:
    """Load and validate the routines file at ``path``; every keyframe target must lie within
    ``limits`` (joint name -> (lower, upper) rad, e.g. ``Robot.joints.limits()``). Problems
    raise :class:`ConfigError` naming the offending key."""
    book = validate(DanceBook, read_yaml(path), str(path))
    problems = [
        f"routines[{r}].keyframes[{k}].joints.{name}: {angle:g} rad is outside the joint's "
        f"limits [{limits[name][0]:.3f}, {limits[name][1]:.3f}]"
        for r, routine in enumerate(book.routines)
        for k, frame in enumerate(routine.keyframes)
        for name, angle in frame.targets().items()
        if not limits[name][0] <= angle <= limits[name][1]]
    if problems:
        raise ConfigError(str(path), problems)
    return book


def song_names(path: str | Path = DEFAULT_DANCES) -> dict[str, tuple[str, ...]]:
    """The songs of the routines file: each title with the phrases that ask for it (the
    title and its aliases, lower case), in the file's order."""
    book = validate(DanceBook, read_yaml(path), str(path))
    return {r.title: tuple(dict.fromkeys(s.lower() for s in (r.title, *r.aliases)))
            for r in book.routines}
