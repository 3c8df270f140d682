from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Literal

import pytest

from radial_ibvs_gym.config import ConfigError, config_path, configs_dir, from_mapping, load_yaml


@dataclass(frozen=True)
class Inner:
    gain: float = 1.0
    mode: Literal["scale", "clip"] = "scale"

    def __post_init__(self) -> None:
        if not self.gain > 0:
            raise ValueError(f"gain must be positive, got {self.gain!r}")


@dataclass(frozen=True)
class Outer:
    name: str
    offset: tuple[float, float] = (0.0, 0.0)
    points: tuple[tuple[float, float, float], ...] = ()
    inner: Inner = field(default_factory=Inner)
    limit: float | None = None
    count: int = 3
    flag: bool = False


def test_builds_nested_dataclasses_and_tuples() -> None:
    cfg = from_mapping(
        Outer,
        {"name": "x", "offset": [1, 2], "points": [[1, 2, 3]], "inner": {"gain": 2}, "limit": 5},
    )
    assert cfg == Outer("x", (1.0, 2.0), ((1.0, 2.0, 3.0),), Inner(2.0), 5.0)
    assert isinstance(cfg.offset[0], float)


def test_yaml_inf_and_scientific_strings_become_floats() -> None:
    assert from_mapping(Outer, {"name": "x", "limit": "inf"}).limit == math.inf
    assert from_mapping(Outer, {"name": "x", "limit": "1e-3"}).limit == 1e-3


@pytest.mark.parametrize(
    ("mapping", "match"),
    [
        ({"name": "x", "offst": [0, 0]}, r"unknown key\(s\) \['offst'\]; valid keys"),
        ({"name": "x", "inner": {"gian": 1}}, r"inner: unknown key\(s\) \['gian'\]"),
        ({}, "missing required key 'name'"),
        ({"name": "x", "offset": [1]}, r"offset: expected 2 items"),
        ({"name": "x", "count": 1.5}, "count: expected an integer"),
        ({"name": "x", "count": True}, "count: expected an integer"),
        ({"name": "x", "flag": "yes"}, "flag: expected true or false"),
        ({"name": "x", "inner": {"mode": "wrap"}}, r"inner.mode: 'wrap' is not one of"),
        ({"name": "x", "inner": {"gain": -1}}, "gain must be positive, got -1.0"),
        ({"name": "x", "limit": "abc"}, "limit: 'abc' matches none of"),
        ({"name": 3}, "name: expected a string"),
    ],
)
def test_bad_configs_name_the_key(mapping: dict, match: str) -> None:
    with pytest.raises(ConfigError, match=match):
        from_mapping(Outer, mapping)


def test_load_yaml_with_overrides(tmp_path: Path) -> None:
    path = tmp_path / "c.yaml"
    path.write_text("name: file\ncount: 4\ninner:\n  gain: 3.5\n")
    cfg = load_yaml(Outer, path, count=7)
    assert (cfg.name, cfg.count, cfg.inner.gain) == ("file", 7, 3.5)
    with pytest.raises(ConfigError, match=r"c.yaml: .*unknown key\(s\) \['cout'\]"):
        load_yaml(Outer, path, cout=7)


def test_load_yaml_rejects_a_non_mapping_file(tmp_path: Path) -> None:
    path = tmp_path / "c.yaml"
    path.write_text("- 1\n- 2\n")
    with pytest.raises(ConfigError, match="top level must be a mapping"):
        load_yaml(Outer, path)


def test_config_path_lists_available_names() -> None:
    assert configs_dir().is_dir()
    with pytest.raises(ConfigError, match=r"unknown cameras config 'nope'; available: \["):
        config_path("cameras", "nope")
