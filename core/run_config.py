"""The configuration of a training run: ``resolved_config.yaml`` in its folder.

A fresh run stores the configuration it resolved (defaults, ``--config`` and the options
that change it); a resumed run trains with that stored configuration and nothing else.
:func:`config_for` gives a ``companion train ...`` handler its configuration under this rule,
and :func:`refuse_changes` names every setting that a configuration given to a resumed run
would change, as a dotted path with both values.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar

import yaml
from pydantic import BaseModel

from core.config_files import read_yaml, validate
from core.errors import UserError

CONFIG_FILE = "resolved_config.yaml"
CHECKPOINT_FILE = "checkpoint.pt"
M = TypeVar("M", bound=BaseModel)
_ABSENT = object()


def plain(config: BaseModel) -> dict[str, Any]:
    """``config`` as the plain YAML data it is stored as."""
    return config.model_dump(mode="json", by_alias=True)


def write_config(out_dir: Path, config: BaseModel) -> None:
    """Store ``config`` as the run's ``resolved_config.yaml``."""
    (out_dir / CONFIG_FILE).write_text(yaml.safe_dump(plain(config), sort_keys=False))


def stored_config(model: type[M], out_dir: Path,
                  error: type[UserError] = UserError) -> M | None:
    """The run's stored configuration validated by ``model``; None when it has none, and
    ``error`` when it has none but a checkpoint (whose configuration is then unknown)."""
    path = out_dir / CONFIG_FILE
    if path.exists():
        return validate(model, read_yaml(path), str(path))
    if (out_dir / CHECKPOINT_FILE).exists():
        raise error(f"{out_dir}: {CHECKPOINT_FILE} has no {CONFIG_FILE} beside it, so the "
                    "run's configuration is unknown; train into a new --out folder")
    return None


def differences(run: Any, given: Any, at: str = "") -> list[tuple[str, Any, Any]]:
    """``(dotted path, run's value, given value)`` for every setting that differs."""
    if not (isinstance(run, dict) and isinstance(given, dict)):
        return [] if run == given else [(at or "(top level)", run, given)]
    keys = [*run, *(k for k in given if k not in run)]
    return [d for k in keys for d in differences(run.get(k, _ABSENT), given.get(k, _ABSENT),
                                                 f"{at}.{k}" if at else str(k))]


def _text(value: Any) -> str:
    return "nothing" if value is _ABSENT else str(value)


def refuse_changes(out_dir: Path, run: BaseModel, given: BaseModel, source: str,
                   error: type[UserError] = UserError) -> None:
    """Raise ``error`` naming each setting where ``given`` differs from the run's stored
    configuration ``run``; ``source`` says where ``given`` comes from and ends in a verb
    (``--config gives``)."""
    changed = differences(plain(run), plain(given))
    if changed:
        lines = "\n".join(f"  {path}: run has {_text(a)}, {source} {_text(b)}"
                          for path, a, b in changed)
        raise error(f"{out_dir / CONFIG_FILE}: a resumed run keeps its own configuration, "
                    f"which this would change:\n{lines}\n"
                    "resume without those options, or train into a new --out folder")


def config_for(args: argparse.Namespace, model: type[M], load: Callable[[], M],
               *options: str) -> M:
    """The configuration of ``companion train ...`` into ``args.out``: ``load()`` for a fresh
    run; with ``args.resume``, the run's stored configuration. ``options`` name the ``args``
    attributes that shape the configuration (``config``, ``data``, ...): when a resumed run
    is given any of them, what they resolve to must equal the stored configuration."""
    if not args.resume:
        return load()
    stored = stored_config(model, args.out)
    if stored is None:
        return load()
    given = [f"--{name.replace('_', '-')}" for name in options
             if getattr(args, name) not in (None, False)]
    if given:
        verb = "gives" if len(given) == 1 else "give"
        refuse_changes(args.out, stored, load(), f"{' and '.join(given)} {verb}")
    return stored
