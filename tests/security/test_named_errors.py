"""Bad input gets a named error (the file, the key, the value), never a raw traceback.

The cases a probe of hostile inputs found still raw: duplicate YAML keys, a ``base:`` out of
the config trees, a YAML error that quoted the file's text, a ``scenario`` that is not a
name, a training section with keywords the algorithm does not take, an ``nn`` class that is
not an activation, a dataset id that climbs out of ``--out``, a model folder nested without
end, and a pickled model loaded without a word.
"""

from __future__ import annotations

from pathlib import Path

import gymnasium as gym
import pytest
import yaml

import radial_ibvs_gym  # noqa: F401  (registers the environments)
from radial_ibvs_agents.learned.training.zoo_config import load_train_config
from radial_ibvs_gym.config import ConfigError, read_yaml, read_yaml_with_base

ROOT = Path(__file__).resolve().parents[2]
TRAIN = ROOT / "configs" / "agents" / "ppo_parking.yaml"


def test_duplicate_yaml_keys_are_refused() -> None:
    with pytest.raises(ConfigError, match=r"line 3: duplicate key 'n_envs'"):
        read_yaml("n_envs: 8\nseed: 1\nn_envs: 4096\n", where="x.yaml")


def test_a_yaml_error_names_the_line_not_the_text(tmp_path: Path) -> None:
    secret = tmp_path / "secret.yaml"
    secret.write_text("root:x:0:0:root:/root:/bin/bash\n  bad: [\n")
    with pytest.raises(ConfigError, match="line") as error:
        read_yaml(secret)
    assert "/bin/bash" not in str(error.value) and "root:x" not in str(error.value)


@pytest.mark.parametrize("base", ["/etc/hostname.yaml", "../../../../../../etc/passwd.yaml"])
def test_a_base_out_of_the_config_trees_is_refused(tmp_path: Path, base: str) -> None:
    config = tmp_path / "configs" / "mine.yaml"
    config.parent.mkdir()
    config.write_text(f"base: {base}\nn_envs: 1\n")
    with pytest.raises(ConfigError, match="base"):
        read_yaml_with_base(config)


def test_a_base_beside_the_config_or_in_the_shipped_trees_is_read(tmp_path: Path) -> None:
    (tmp_path / "parent.yaml").write_text("a: 1\nb: 2\n")
    child = tmp_path / "child.yaml"
    child.write_text("base: parent.yaml\nb: 3\n")
    assert read_yaml_with_base(child) == {"a": 1, "b": 3}
    overlay = ROOT / "research" / "configs" / "dagger_planner_set_line.yaml"
    assert isinstance(read_yaml_with_base(overlay), dict)  # ../../configs/agents/...
    outside = tmp_path / "sub" / "deeper.yaml"
    outside.parent.mkdir()
    outside.write_text("base: ../parent.yaml\n")
    with pytest.raises(ConfigError, match="leaves the folders"):
        read_yaml_with_base(outside)
    assert read_yaml_with_base(outside, any_base=True) == {"a": 1, "b": 2}


def test_a_base_that_is_not_a_mapping_is_named_not_quoted(tmp_path: Path) -> None:
    (tmp_path / "text.yaml").write_text("just a line of someone's text\n")
    child = tmp_path / "child.yaml"
    child.write_text("base: text.yaml\n")
    with pytest.raises(ConfigError, match="must be a mapping, got a str") as error:
        read_yaml_with_base(child)
    assert "someone" not in str(error.value)


@pytest.mark.parametrize("scenario", [{"a": 1}, ["paper-sim"], 3])
def test_a_scenario_that_is_not_a_name_is_named(scenario: object) -> None:
    with pytest.raises(ValueError, match="scenario must be a shipped name or the path"):
        gym.make("RadialIBVS/Parking-v0", scenario=scenario)


@pytest.mark.parametrize(
    ("changes", "named"),
    [
        ({"seed": 3}, "'seed' is set by --seed"),
        ({"foo_bar": 1}, "takes no keyword 'foo_bar'"),
        ({"n_step": 64}, "did you mean 'n_steps'"),
    ],
)
def test_a_training_keyword_the_algorithm_does_not_take_is_named(
    tmp_path: Path, changes: dict, named: str
) -> None:
    from radial_ibvs_agents.learned.training.train import train

    data = yaml.safe_load(TRAIN.read_text())
    data["RadialIBVS/Parking-v0"].update(changes)
    path = tmp_path / "bad.yaml"
    path.write_text(yaml.safe_dump(data))
    out = tmp_path / "out"
    with pytest.raises(ValueError, match=named) as error:
        train(load_train_config(path), out, progress=False)
    assert "bad.yaml" in str(error.value)
    assert not out.exists()  # checked before anything was written


def test_an_nn_class_that_is_not_an_activation_is_refused(tmp_path: Path) -> None:
    data = yaml.safe_load(TRAIN.read_text())
    data["RadialIBVS/Parking-v0"]["policy_kwargs"] = "dict(activation_fn=nn.Module)"
    path = tmp_path / "bad.yaml"
    path.write_text(yaml.safe_dump(data))
    with pytest.raises(ValueError, match=r"nn\.Module is not an activation"):
        load_train_config(path)


@pytest.mark.parametrize("dataset_id", ["../../x-v0", "/tmp/x-v0", "ns/../x-v0", "no-version"])
def test_a_dataset_id_that_leaves_out_is_refused_before_any_episode(
    tmp_path: Path, dataset_id: str
) -> None:
    from radial_ibvs_agents.experiments.collect import collect

    out = tmp_path / "out"
    with pytest.raises(ValueError, match="dataset id"):
        collect("ibvs", "paper-sim", 1, out, dataset_id=dataset_id, progress=False)
    assert sorted(p.name for p in tmp_path.iterdir()) in ([], ["out"])


def test_a_model_folder_nested_without_end_is_named(tmp_path: Path) -> None:
    from radial_ibvs_agents.experiments import store

    model = tmp_path / "model"
    deep = model
    for _ in range(store.MAX_MODEL_DEPTH + 5):
        deep = deep / "d"
    deep.mkdir(parents=True)
    with pytest.raises(ValueError, match="MAX_MODEL_DEPTH"):
        store._model_files(model)


def test_a_trusted_pickle_is_loaded_with_a_warning() -> None:
    from radial_ibvs_agents import load
    from radial_ibvs_agents.learned import MODELS_DIR
    from radial_ibvs_agents.learned.files.loading import PickleLoadWarning

    with pytest.warns(PickleLoadWarning, match="through its pickles"):
        load(MODELS_DIR / "dagger-student" / "model.zip", trust_pickle=True)


def test_the_last_silent_or_raw_cases_are_named(tmp_path: Path) -> None:
    from radial_ibvs_gym.physics import RobotConfig

    with pytest.raises(ValueError, match="goal_image_frames must be an integer"):
        gym.make("RadialIBVS/Parking-v0", goal_image_frames=None)
    with pytest.raises(ValueError, match="MIN_ROBOT_M"):
        RobotConfig(length=1e-300)  # pymunk cannot simulate a body that small
    for mode in (None, 1):
        with pytest.raises(ValueError, match="unknown autoreset_mode"):
            gym.make_vec(
                "RadialIBVS/Parking-v0",
                num_envs=2,
                vectorization_mode="vector_entry_point",
                autoreset_mode=mode,
                physics="kinematic",
            )


def test_a_full_disk_names_the_file(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    import errno

    from radial_ibvs_agents import io as project_io

    def full(*_: object) -> None:
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(project_io.os, "replace", full)
    with pytest.raises(OSError, match=r"cannot write .*x\.json: No space left") as error:
        project_io.write_atomic(tmp_path / "x.json", "{}")
    assert error.value.errno == errno.ENOSPC
    assert list(tmp_path.iterdir()) == []  # no temporary file left


def test_a_policy_description_or_statistics_file_that_lies_is_named(tmp_path: Path) -> None:
    import json
    import shutil

    import numpy as np

    from radial_ibvs_agents import load
    from radial_ibvs_agents.learned import MODELS_DIR

    model = tmp_path / "model"
    shutil.copytree(MODELS_DIR / "dagger-student", model)
    described = json.loads((model / "policy.json").read_text())
    (model / "policy.json").write_text(json.dumps({**described, "format_version": True}))
    with pytest.raises(ValueError, match="format_version True is unknown"):
        load(model)
    (model / "policy.json").write_text(json.dumps(described))
    with np.load(model / "normalization.npz") as data:
        arrays = {k: data[k] for k in data.files}
    key = next(k for k in arrays if k.startswith("var/"))
    arrays[key] = -np.abs(arrays[key]) - 1.0
    np.savez(model / "normalization.npz", **arrays)
    with pytest.raises(ValueError, match=r"normalization\.npz: the statistics of .* negative"):
        load(model)
