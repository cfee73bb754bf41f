"""Property tests of the scenario parser: whatever a scenario file holds, loading it ends in
a valid scenario or a ConfigError naming the problems, never another exception."""

from __future__ import annotations

import copy
import math

import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from test_scenario import minimal

from core.config_files import ConfigError
from sim.scenario import Scenario, load_scenario

NASTY = st.one_of(
    st.none(), st.booleans(), st.integers(min_value=-(10**30), max_value=10**30),
    st.floats(allow_nan=True, allow_infinity=True), st.text(max_size=40),
    st.lists(st.integers(), max_size=3), st.dictionaries(st.text(max_size=5), st.integers(),
                                                         max_size=2))


def _paths(node: object, prefix: tuple = ()) -> list[tuple]:
    """Every key path of a nested dict/list document."""
    out = [prefix] if prefix else []
    if isinstance(node, dict):
        for key, value in node.items():
            out += _paths(value, (*prefix, key))
    elif isinstance(node, list):
        for i, value in enumerate(node):
            out += _paths(value, (*prefix, i))
    return out


PATHS = _paths(minimal())
FUZZ = settings(max_examples=150, deadline=None,
                suppress_health_check=[HealthCheck.function_scoped_fixture])


def _mutate(doc: dict, path: tuple, value: object, delete: bool) -> dict:
    doc = copy.deepcopy(doc)
    node = doc
    for key in path[:-1]:
        node = node[key]
    if delete and isinstance(node, dict):
        del node[path[-1]]
    else:
        node[path[-1]] = value
    return doc


def _loads_or_names_problems(tmp_path, text: str) -> None:
    path = tmp_path / "scenario.yaml"
    path.write_text(text, encoding="utf-8")
    try:
        scenario = load_scenario(path)
    except ConfigError as exc:
        assert exc.problems and all(isinstance(p, str) and p for p in exc.problems)
        return
    assert isinstance(scenario, Scenario)
    assert math.isfinite(scenario.duration) and 0 <= scenario.seed < 2**32


@FUZZ
@given(st.sampled_from(PATHS), NASTY, st.booleans())
def test_any_one_bad_value_is_a_config_error(tmp_path, path, value, delete):
    doc = _mutate(minimal(), path, value, delete)
    _loads_or_names_problems(tmp_path, yaml.safe_dump(doc, sort_keys=False))


@FUZZ
@given(st.text(max_size=200))
def test_any_text_is_a_scenario_or_a_config_error(tmp_path, text):
    _loads_or_names_problems(tmp_path, text)
