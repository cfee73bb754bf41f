"""The sweep spec: a validated YAML file naming what to run (docs/sweeps.md).

The smallest spec is ``{worlds: [worlds/a.yaml], seeds: [0, 1], duration: 60}``. Lists of
``worlds``, ``seeds``, ``personalities`` and ``policies`` (``null``: the scenario's or the
shipped one) and an optional ``faults`` file make a grid, every combination once; or
``runs:`` lists the entries one by one. ``checks`` are bounds on metrics each run must
meet (``{rsr: {min: 0.99}}``). ``hearing: fast`` hears every run's lines from the acoustics'
levels alone (no voices synthesised or recognised). Paths are relative to the spec file.
"""

from __future__ import annotations

import hashlib
import itertools
import json
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Literal

from pydantic import Field, model_validator

from core.config_files import ConfigError, StrictModel, read_yaml, validate
from core.limits import MAX_DURATION_S, SEED_MAX
from core.paths import REPO_ROOT

GRID_KEYS = {"world": "worlds", "personality": "personalities", "policy": "policies",
             "faults": "faults"}


class Bounds(StrictModel):
    """What a metric must stay within."""

    min: float | None = None
    max: float | None = None


class RunEntry(StrictModel):
    """One run of the explicit ``runs:`` list."""

    world: Path
    seed: int = Field(default=0, ge=0, le=SEED_MAX)
    duration: float | None = Field(default=None, gt=0, le=MAX_DURATION_S)
    personality: Path | None = None
    policy: Path | None = None
    faults: Path | None = None


class TrainSweep(StrictModel):
    """DQN trainings over seeds (``train_policy:``), each then tested against the
    homeostatic rule on the same ``episodes`` (seeded by ``eval_seed``)."""

    config: Path | None = None
    personality: Path | None = None
    seeds: tuple[int, ...] = Field(min_length=1)
    episodes: int = Field(default=100, ge=1, le=100_000)
    eval_seed: int = Field(default=0, ge=0, le=SEED_MAX)


class SweepSpec(StrictModel):
    """A sweep: a grid over lists, an explicit list of runs, or trainings over seeds."""

    worlds: tuple[Path, ...] = ()
    seeds: tuple[int, ...] = Field(default=(0,), min_length=1)
    duration: float | None = Field(default=None, gt=0, le=MAX_DURATION_S)
    personalities: tuple[Path | None, ...] = (None,)
    policies: tuple[Path | None, ...] = (None,)
    faults: Path | None = None
    hearing: Literal["audio", "fast"] = "audio"
    runs: tuple[RunEntry, ...] = ()
    train_policy: TrainSweep | None = None
    checks: dict[str, Bounds] = Field(default_factory=dict)

    @model_validator(mode="after")
    def _something(self) -> SweepSpec:
        if sum((bool(self.worlds), bool(self.runs), self.train_policy is not None)) != 1:
            raise ValueError("give one of `worlds` (a grid), `runs` (a list) or "
                             "`train_policy` (trainings over seeds)")
        if any(not 0 <= s <= SEED_MAX for s in self.seeds):
            raise ValueError(f"seeds must lie between 0 and {SEED_MAX}")
        return self


class Entry:
    """What every sweep entry (a dataclass) shares: its hash and the option it compares."""

    personality: str | None
    policy: str | None = None
    faults: str | None = None

    @property
    def key(self) -> str:
        """A short hash of the entry: its folder name and the mark of its metrics. Files of
        the project count by their path within it, so a clone elsewhere (another machine,
        another folder) finds its finished runs."""
        fields = {k: _portable(v) for k, v in asdict(self).items()  # type: ignore[call-overload]
                  if (k, v) != ("hearing", "audio")}   # the keys of sweeps made before it
        text = json.dumps(fields, sort_keys=True)
        return hashlib.sha256(text.encode()).hexdigest()[:12]

    def option(self) -> str:
        """What this entry compares beyond its world and seed (personality, policy, faults)."""
        parts = [f"{k}={Path(v).stem}" for k, v in (("personality", self.personality),
                                                    ("policy", self.policy),
                                                    ("faults", self.faults)) if v]
        if getattr(self, "hearing", "audio") != "audio":
            parts.append(f"hearing={self.hearing}")
        return ", ".join(parts) or "default"


@dataclass(frozen=True)
class Run(Entry):
    """One run of a sweep, with absolute paths."""

    world: str
    seed: int
    duration: float | None
    personality: str | None
    policy: str | None
    faults: str | None
    hearing: str = "audio"

    @property
    def name(self) -> str:
        """The run's folder name: world, seed and the entry's hash."""
        return f"{Path(self.world).stem}-seed{self.seed}-{self.key}"


@dataclass(frozen=True)
class TrainRun(Entry):
    """One DQN training of a sweep, with absolute paths (no policy or faults file)."""

    config: str | None
    personality: str | None
    seed: int
    episodes: int
    eval_seed: int
    world = "dqn_training"   # the report's group

    @property
    def name(self) -> str:
        """The training's folder name: seed and the entry's hash."""
        return f"train-policy-seed{self.seed}-{self.key}"


def _portable(value: object) -> object:
    """A path inside the project as its path from the project's root; anything else as is."""
    if isinstance(value, str) and value.startswith(str(REPO_ROOT) + "/"):
        return value[len(str(REPO_ROOT)) + 1:]
    return value


def _absolute(base: Path, path: Path | None) -> str | None:
    return None if path is None else str((base / path).resolve())


def load_sweep(path: str | Path) -> tuple[SweepSpec, list[Run | TrainRun]]:
    """The spec at ``path`` and its runs; missing files are named by key."""
    path = Path(path)
    spec = validate(SweepSpec, read_yaml(path), str(path))
    base = path.parent
    if spec.train_policy is not None:
        return spec, _trainings(spec.train_policy, base, str(path))
    entries = spec.runs or [RunEntry(world=w, seed=s, duration=spec.duration, personality=pe,
                                     policy=po, faults=spec.faults)
                            for w, s, pe, po in itertools.product(
                                spec.worlds, spec.seeds, spec.personalities, spec.policies)]
    runs, problems = [], []
    for i, e in enumerate(entries):
        run = Run(_absolute(base, e.world), e.seed, e.duration,  # type: ignore[arg-type]
                  _absolute(base, e.personality), _absolute(base, e.policy),
                  _absolute(base, e.faults), spec.hearing)
        for key in ("world", "personality", "policy", "faults"):
            value = getattr(run, key)
            if value is not None and not Path(value).is_file():
                where = f"runs[{i}].{key}" if spec.runs else GRID_KEYS[key]
                problems.append(f"{where}: file not found: {value}")
        runs.append(run)
    if problems:
        raise ConfigError(str(path), sorted(set(problems)))
    return spec, list(dict.fromkeys(runs))


def _trainings(t: TrainSweep, base: Path, source: str) -> list[Run | TrainRun]:
    config, personality = _absolute(base, t.config), _absolute(base, t.personality)
    problems = [f"train_policy.{key}: file not found: {value}"
                for key, value in (("config", config), ("personality", personality))
                if value is not None and not Path(value).is_file()]
    if problems:
        raise ConfigError(source, problems)
    return list(dict.fromkeys(TrainRun(config, personality, s, t.episodes, t.eval_seed)
                              for s in t.seeds))
