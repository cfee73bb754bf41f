"""Loading YAML configuration files into validated pydantic models.

Every config in the project goes through :func:`load_model`: YAML is parsed safely,
an optional user file is deep-merged over a packaged default, unknown keys are
errors, and every problem is reported with its dotted path (``reward.kappa: ...``).
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any, TypeVar

import yaml
from pydantic import BaseModel, ConfigDict, ValidationError

from core.errors import UserError
from core.files import FileReadError, read_text
from core.paths import DEFAULTS_DIR

M = TypeVar("M", bound=BaseModel)


class ConfigError(UserError, ValueError):
    """A configuration file is unreadable or invalid; ``problems`` lists ``path: message``."""

    def __init__(self, source: str, problems: list[str]) -> None:
        self.source = source
        self.problems = problems
        lines = "\n".join(f"  {p}" for p in problems)
        super().__init__(f"{source}: invalid configuration\n{lines}")


class StrictModel(BaseModel):
    """Base for config schemas: unknown keys are rejected, numbers are finite and instances
    are immutable."""

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)


class _UniqueKeyLoader(yaml.SafeLoader):
    """The safe loader, refusing a mapping that repeats a key (YAML would keep the last)."""

    def construct_mapping(self, node: yaml.MappingNode, deep: bool = False) -> dict:
        seen: set[Any] = set()
        for key_node, _ in node.value:
            key = self.construct_object(key_node, deep=True)  # type: ignore[no-untyped-call]
            if isinstance(key, (str, int, float, bool)) and key in seen:
                raise yaml.constructor.ConstructorError(
                    "while reading a mapping", node.start_mark,
                    f"found the key {key!r} twice", key_node.start_mark)
            seen.add(key)
        return super().construct_mapping(node, deep=deep)


def _yaml_problem(exc: yaml.YAMLError) -> str:
    """A YAML error in one line: where (line and column, from 1) and what."""
    if isinstance(exc, yaml.MarkedYAMLError) and exc.problem_mark is not None:
        mark = exc.problem_mark
        return f"line {mark.line + 1}, column {mark.column + 1}: {exc.problem}"
    return " ".join(str(exc).split())


def parse_yaml(text: str, source: str) -> Any:
    """Parse ``text`` with the safe loader (no code, no duplicate keys); problems raise
    :class:`ConfigError` naming ``source``."""
    try:
        return yaml.load(text, Loader=_UniqueKeyLoader)
    except yaml.YAMLError as exc:
        raise ConfigError(source, [f"not valid YAML: {_yaml_problem(exc)}"]) from None
    except RecursionError:
        raise ConfigError(source, ["not valid YAML: nested too deeply"]) from None


def read_yaml(path: str | Path) -> dict[str, Any]:
    """Parse a YAML mapping with the safe loader; raise :class:`ConfigError` when the file
    cannot be read (:func:`core.files.read_text`) or is not one."""
    path = Path(path)
    try:
        text = read_text(path)
    except FileReadError as exc:
        raise ConfigError(str(path), [str(exc).removeprefix(f"{path}: ")]) from None
    data = parse_yaml(text, str(path))
    if data is None:
        return {}
    if not isinstance(data, dict):
        raise ConfigError(str(path), [f"top level must be a mapping, got {type(data).__name__}"])
    return data


def deep_merge(base: Mapping[str, Any], override: Mapping[str, Any]) -> dict[str, Any]:
    """Return ``base`` updated by ``override``; nested mappings merge key by key."""
    merged = dict(base)
    for key, value in override.items():
        if isinstance(value, Mapping) and isinstance(merged.get(key), Mapping):
            merged[key] = deep_merge(merged[key], value)
        else:
            merged[key] = value
    return merged


def format_loc(loc: tuple[int | str, ...]) -> str:
    """Render a pydantic error location as ``people[2].events[0].at``."""
    out = ""
    for part in loc:
        if isinstance(part, int):
            out += f"[{part}]"
        else:
            out += f".{part}" if out else str(part)
    return out or "(top level)"


def validate(model: type[M], data: Mapping[str, Any], source: str) -> M:
    """Validate ``data`` against ``model``, turning pydantic errors into a :class:`ConfigError`."""
    try:
        return model.model_validate(data)
    except ValidationError as exc:
        problems = []
        for err in exc.errors():
            msg = err["msg"]
            if err["type"] == "extra_forbidden":
                msg = "unknown key"
            problems.append(f"{format_loc(err['loc'])}: {msg}")
        raise ConfigError(source, problems) from None


def load_model(model: type[M], default_name: str, path: str | Path | None = None) -> M:
    """Load ``defaults/<default_name>`` merged with the optional user file at ``path``."""
    data = read_yaml(DEFAULTS_DIR / default_name)
    source = f"defaults/{default_name}"
    if path is not None:
        data = deep_merge(data, read_yaml(path))
        source = str(path)
    return validate(model, data, source)
