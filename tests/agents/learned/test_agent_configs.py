"""The agents' configs: the shipped ones in configs/agents, the studies' overlays in research/.

A shipped config is a whole file (rl-zoo3 reads it as it is); a research config is a short
overlay (``base:``) of the config it varies. Every shipped model names the config that made it,
by a path that exists, holding the settings the model records.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from radial_ibvs_agents.learned import MODELS_DIR
from radial_ibvs_agents.learned.dagger.distill_config import load_dagger_config
from radial_ibvs_agents.learned.training.zoo_config import load_train_config
from radial_ibvs_gym.config import ConfigError, read_yaml, read_yaml_with_base

ROOT = Path(__file__).resolve().parents[3]
SHIPPED = sorted((ROOT / "configs" / "agents").glob("*.yaml"))
RESEARCH = sorted((ROOT / "research" / "configs").glob("*.yaml"))
MODELS = sorted(p for p in MODELS_DIR.iterdir() if p.is_dir())


def _load(path: Path) -> object:
    if path.name.startswith("dagger"):
        return load_dagger_config(path)
    return load_train_config(path)


def test_the_shipped_configs_are_few_and_whole():
    assert 1 <= len(SHIPPED) <= 8, [p.name for p in SHIPPED]
    for path in SHIPPED:
        assert "base" not in read_yaml(path), f"{path.name}: a shipped config is a whole file"


@pytest.mark.parametrize("path", SHIPPED + RESEARCH, ids=lambda p: p.name)
def test_every_agent_config_loads(path: Path) -> None:
    config = _load(path)
    if path.name.startswith("dagger"):
        assert config.teacher == "planner"  # type: ignore[attr-defined]


@pytest.mark.parametrize("path", RESEARCH, ids=lambda p: p.name)
def test_a_research_config_is_an_overlay_shorter_than_what_it_means(path: Path) -> None:
    data = read_yaml(path)
    if "base" not in data:  # a study's own root (an early design, far from the shipped ones)
        return
    import yaml

    merged = read_yaml_with_base(path)
    assert "base" not in merged
    body = {k: v for k, v in data.items() if k != "base"}
    assert len(yaml.safe_dump(body)) < len(yaml.safe_dump(merged))


@pytest.mark.parametrize("model", MODELS, ids=lambda p: p.name)
def test_each_shipped_model_names_the_config_that_made_it(model: Path) -> None:
    metadata = json.loads((model / "metadata.json").read_text())
    recorded = metadata["config"]
    path = ROOT / recorded["file"]
    assert path.is_file(), f"{model.name}: its config {recorded['file']} does not exist"
    assert path.parent == ROOT / "configs" / "agents"
    data = read_yaml_with_base(path)
    if "dagger" in recorded:
        assert data["dagger"] == recorded["dagger"]
    else:
        section = dict(data[recorded["env_id"]])
        if "--total-timesteps" in metadata["command"]:  # the command set the budget
            given = metadata["command"].split("--total-timesteps")[1].split()[0]
            assert section.pop("n_timesteps") == float(given)
            recorded["section"].pop("n_timesteps")
        assert section == recorded["section"]
        assert data["radial_ibvs_gym"] == recorded["meta"]


def test_the_old_student_name_is_refused_with_its_new_name():
    from radial_ibvs_agents import make_policy

    with pytest.raises(ValueError, match="dagger-student"):
        make_policy("ppo-student")


def test_an_overlay_changes_only_what_it_names(tmp_path: Path) -> None:
    (tmp_path / "base.yaml").write_text("a: {x: 1, y: 2}\nb: [1, 2]\nc: 3\n")
    (tmp_path / "mid.yaml").write_text("base: base.yaml\na: {y: 5}\nc: null\n")
    (tmp_path / "top.yaml").write_text("base: mid.yaml\nb: [7]\n")
    assert read_yaml_with_base(tmp_path / "top.yaml") == {"a": {"x": 1, "y": 5}, "b": [7]}


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("base: 3\n", "base must be the path of a .yaml file"),
        ("base: missing.yaml\n", "no such file"),
        ("base: loop.yaml\n", "comes back to a file"),
    ],
)
def test_bad_overlays_are_named(tmp_path: Path, text: str, match: str) -> None:
    path = tmp_path / "loop.yaml"
    path.write_text(text)
    with pytest.raises(ConfigError, match=match) as caught:
        read_yaml_with_base(path)
    assert "loop.yaml" in str(caught.value)


def test_a_chain_of_bases_is_bounded(tmp_path: Path) -> None:
    from radial_ibvs_gym.limits import MAX_CONFIG_BASES

    (tmp_path / "c0.yaml").write_text("a: 1\n")
    for k in range(1, MAX_CONFIG_BASES + 2):
        (tmp_path / f"c{k}.yaml").write_text(f"base: c{k - 1}.yaml\nb{k}: {k}\n")
    assert read_yaml_with_base(tmp_path / f"c{MAX_CONFIG_BASES - 1}.yaml")["a"] == 1
    with pytest.raises(ConfigError, match="MAX_CONFIG_BASES"):
        read_yaml_with_base(tmp_path / f"c{MAX_CONFIG_BASES + 1}.yaml")
