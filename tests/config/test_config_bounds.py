"""Bounded configs: no YAML bombs, short error messages, documented limits, a loader fuzz."""

from __future__ import annotations

import math
import time
from pathlib import Path

import gymnasium as gym
import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import radial_ibvs_gym  # noqa: F401
from radial_ibvs_gym.config import ConfigError, configs_dir, read_yaml
from radial_ibvs_gym.limits import (
    MAX_CONFIG_BYTES,
    MAX_CONFIG_DEPTH,
    MAX_LANDMARKS,
    MAX_NUM_ENVS,
    MAX_OBSTACLES,
)
from radial_ibvs_gym.scenarios import load_scenario

BOMB = """
a: &a ["lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol"]
b: &b [*a, *a, *a, *a, *a, *a, *a, *a, *a]
c: &c [*b, *b, *b, *b, *b, *b, *b, *b, *b]
d: &d [*c, *c, *c, *c, *c, *c, *c, *c, *c]
e: &e [*d, *d, *d, *d, *d, *d, *d, *d, *d]
f: &f [*e, *e, *e, *e, *e, *e, *e, *e, *e]
g: &g [*f, *f, *f, *f, *f, *f, *f, *f, *f]
h: &h [*g, *g, *g, *g, *g, *g, *g, *g, *g]
name: [*h, *h, *h, *h, *h, *h, *h, *h, *h]
"""
LAB = yaml.safe_load((configs_dir() / "scenarios" / "paper-lab.yaml").read_text())


def _write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "scenario.yaml"
    path.write_text(text)
    return path


def test_a_yaml_bomb_is_refused_at_once(tmp_path: Path) -> None:
    path = _write(tmp_path, BOMB)
    start = time.perf_counter()
    with pytest.raises(ConfigError, match=r"line 2: YAML anchors and aliases") as caught:
        load_scenario(path)
    assert time.perf_counter() - start < 1.0  # it once took 56 s and 11 GB
    assert len(str(caught.value)) < 400


def test_deep_nesting_is_refused_with_its_line(tmp_path: Path) -> None:
    deep = "[" * (MAX_CONFIG_DEPTH + 5) + "]" * (MAX_CONFIG_DEPTH + 5)
    with pytest.raises(ConfigError, match="MAX_CONFIG_DEPTH"):
        load_scenario(_write(tmp_path, f"name: {deep}\n"))
    very_deep = "[" * 100_000 + "]" * 100_000  # once a RecursionError
    with pytest.raises(ConfigError):
        load_scenario(_write(tmp_path, f"name: {very_deep}\n"))


def test_a_huge_file_and_python_tags_are_refused(tmp_path: Path) -> None:
    with pytest.raises(ConfigError, match="MAX_CONFIG_BYTES"):
        load_scenario(_write(tmp_path, "name: x\n" + "#" * (2 << 20)))
    with pytest.raises(ConfigError, match="not valid YAML"):
        load_scenario(_write(tmp_path, "name: !!python/object/apply:os.system ['true']\n"))
    with pytest.raises(ConfigError, match="not valid YAML"):
        read_yaml("a: [1, 2", "--env-kwarg a")


def test_values_in_messages_are_shortened(tmp_path: Path) -> None:
    long_list = "[" + ", ".join(["1"] * 20_000) + "]"
    with pytest.raises(ConfigError) as caught:
        load_scenario(_write(tmp_path, f"name: x\nroom: {long_list}\n"))
    assert len(str(caught.value)) < 700 and "room" in str(caught.value)
    with pytest.raises(ConfigError) as caught:
        load_scenario(_write(tmp_path, "name: x\n" + "k" * 50_000 + ": 1\n"))
    assert len(str(caught.value)) < 700


@pytest.mark.parametrize(
    ("overrides", "limit"),
    [
        ({"random_landmarks": {"count": 100_000}}, "MAX_LANDMARKS"),
        ({"landmarks": [[1.0, 0.0, 1.0]] * (MAX_LANDMARKS + 1)}, "MAX_LANDMARKS"),
        ({"random_obstacles": {"count": [0, 1_000_000]}}, "MAX_OBSTACLES"),
        ({"obstacles": [[3.0, 2.5, 0.1]] * (MAX_OBSTACLES + 1)}, "MAX_OBSTACLES"),
    ],
)
def test_counts_have_limits_that_the_error_names(overrides: dict, limit: str) -> None:
    base = dict(LAB)
    if "random_landmarks" in overrides:
        base.pop("landmarks")
    with pytest.raises(ConfigError, match=limit):
        load_scenario(configs_dir() / "scenarios" / "paper-lab.yaml", **{**base, **overrides})


def test_env_sizes_have_limits_that_the_error_names() -> None:
    with pytest.raises(ValueError, match="MAX_LANDMARKS"):
        gym.make("RadialIBVS/Parking-v0", max_landmarks=10**6)
    with pytest.raises(ValueError, match="MAX_NUM_ENVS"):
        gym.make_vec(
            "RadialIBVS/Parking-v0",
            num_envs=MAX_NUM_ENVS + 1,
            vectorization_mode="vector_entry_point",
        )


FUZZ = settings(
    max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)


# --- a fuzz of the scenario loader: every bad file is a ConfigError, never a raw traceback ----
_scalars = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(min_value=-(10**400), max_value=10**400),
    st.floats(allow_nan=True, allow_infinity=True),
    st.text(max_size=30),
)
_values = st.recursive(
    _scalars,
    lambda inner: st.one_of(
        st.lists(inner, max_size=5), st.dictionaries(st.text(max_size=10), inner, max_size=4)
    ),
    max_leaves=20,
)


def _yaml(value: object) -> str:
    return yaml.safe_dump(value, default_flow_style=True, width=math.inf)


@pytest.mark.slow
@FUZZ
@given(key=st.sampled_from(sorted(LAB)), value=_values)
def test_a_bad_value_of_a_key_gives_a_config_error_naming_it(
    key: str, value: object, tmp_path: Path
) -> None:
    data = {**LAB, key: value}
    try:
        load_scenario(_write(tmp_path, _yaml(data)))
    except ConfigError as error:
        assert key in str(error), str(error)
    except ValueError as error:  # a documented scene check (too few landmarks visible...)
        assert "scenario" in str(error) or "landmark" in str(error), str(error)


@FUZZ
@given(text=st.text(max_size=200))
def test_any_text_loads_or_gives_a_config_error(text: str, tmp_path: Path) -> None:
    try:
        load_scenario(_write(tmp_path, text))
    except ConfigError:
        pass


def test_a_list_of_many_small_values_is_refused_by_its_count(tmp_path: Path) -> None:
    # 300,000 values fit in MAX_CONFIG_BYTES; the parser stops at MAX_CONFIG_NODES of them
    many = "[" + ",".join(["1"] * 300_000) + "]"
    assert len(many) < MAX_CONFIG_BYTES
    with pytest.raises(ConfigError, match=r"line 2: more than MAX_CONFIG_NODES"):
        load_scenario(_write(tmp_path, f"name: x\nlandmarks: {many}\n"))


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("1e6", 1e6),  # YAML 1.1 reads this as a string
        ("-2.5E-3", -2.5e-3),
        (".5", 0.5),
        ("3", 3),
        ("2026-13-45", "2026-13-45"),  # no timestamps: a bad date is a string, not a crash
        ("1e", "1e"),
    ],
)
def test_numbers_read_as_yaml_1_2_reads_them(text: str, expected: object) -> None:
    value = read_yaml(f"a: {text}", "test")["a"]
    assert value == expected and type(value) is type(expected)


def test_an_integer_too_long_to_convert_is_a_named_error() -> None:
    with pytest.raises(ConfigError, match=r"--env-kwarg task: line 1: a value cannot be read"):
        read_yaml("9" * 5000, "--env-kwarg task")
