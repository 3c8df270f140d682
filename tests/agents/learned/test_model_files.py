"""Model files without pickles: safetensors + JSON, and pickled payloads that never run.

A payload here (``pickle_payloads``) only writes a marker file. Each test first shows the
payload is live (loading the file the unsafe way writes the marker), so that "the marker never
appears" means something.
"""

from __future__ import annotations

import json
import shutil
import sys
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest
from pickle_payloads import payload, poison_zip

import radial_ibvs_gym  # noqa: F401
from radial_ibvs_agents import load
from radial_ibvs_agents.cli import main
from radial_ibvs_agents.learned import MODELS_DIR
from radial_ibvs_agents.learned.files.former_paths import (
    FORMER_MODULES,
    current_module,
    current_name,
)
from radial_ibvs_agents.learned.files.model_files import (
    DESCRIPTION,
    WEIGHTS,
    load_policy,
    space_from_json,
    space_to_json,
)
from radial_ibvs_agents.learned.files.saving import save_model_dir
from radial_ibvs_agents.rollouts import make_env

CONFIG = Path(__file__).resolve().parents[3] / "configs" / "agents" / "ppo_parking.yaml"


@pytest.fixture
def poisoned(tmp_path: Path) -> tuple[Path, Path]:
    """A copy of the shipped ``dagger-student`` whose ``model.zip`` carries a payload."""
    model = tmp_path / "ppo-poisoned"
    shutil.copytree(MODELS_DIR / "dagger-student", model)
    marker = tmp_path / "marker"
    poison_zip(model / "model.zip", marker)
    (model / "vecnormalize.pkl").write_bytes(payload(marker))
    return model, marker


def test_the_payload_is_live_when_the_pickles_are_trusted(poisoned: tuple[Path, Path]) -> None:
    model, marker = poisoned
    legacy = model.parent / "legacy"
    legacy.mkdir()
    for name in ("model.zip", "metadata.json", "normalization.npz"):
        shutil.copy(model / name, legacy / name)
    load(legacy, trust_pickle=True)
    assert marker.is_file()


def test_load_reads_the_safe_files_and_never_the_zip(poisoned: tuple[Path, Path]) -> None:
    model, marker = poisoned
    policy = load(model)
    obs, _ = make_env(policy, "paper-lab", {"physics": "kinematic"}).reset(seed=0)
    assert policy.predict(obs)[0].shape == (2,)
    assert not marker.exists()


def test_a_pickled_model_alone_is_refused_without_the_opt_in(
    poisoned: tuple[Path, Path], capsys: pytest.CaptureFixture[str]
) -> None:
    model, marker = poisoned
    (model / WEIGHTS).unlink()
    with pytest.raises(ValueError, match=r"refusing to load .*trust_pickle=True.*--trust-model"):
        load(model)
    with pytest.raises(ValueError, match="refusing"):
        load(model / "model.zip")
    argv = ["evaluate", "--policy", str(model), "--scenario", "paper-lab", "--episodes", "1"]
    assert main(argv) == 2
    assert "--trust-model" in capsys.readouterr().err
    assert main(["benchmark", "--policies", str(model), "--suites", "paper-lab"]) == 2
    assert not marker.exists()


def test_evaluate_and_the_benchmark_workers_never_run_the_payload(
    poisoned: tuple[Path, Path], tmp_path: Path
) -> None:
    model, marker = poisoned
    argv = ["evaluate", "--policy", str(model), "--scenario", "paper-lab", "--episodes", "1"]
    assert main([*argv, "--env-kwarg", "physics=kinematic"]) == 0
    argv = ["benchmark", "--policies", str(model), "--suites", "paper-lab", "--episodes", "2"]
    argv += ["--workers", "2", "--out", str(tmp_path / "bench"), "--no-progress"]
    assert main(argv) == 0
    rows = json.loads((tmp_path / "bench" / "episodes.json").read_text())
    assert len(rows) == 2
    assert not marker.exists()


@pytest.fixture(scope="module")
def trained(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("train") / "ppo"
    argv = ["train", "--config", str(CONFIG), "--total-timesteps", "256", "--out", str(out)]
    assert main([*argv, "--no-progress", "--env-kwarg", "task=1"]) == 0
    return out


@pytest.mark.slow  # trains a model (13 s)
def test_resume_needs_the_plain_observation_statistics(trained: Path, tmp_path: Path) -> None:
    source = tmp_path / "source"
    shutil.copytree(trained, source)
    (source / "normalization.npz").unlink()
    with pytest.raises(ValueError, match=r"normalization\.npz are missing"):
        from radial_ibvs_agents.learned.training.train import train
        from radial_ibvs_agents.learned.training.zoo_config import load_train_config

        train(load_train_config(CONFIG), tmp_path / "x", resume=source, total_timesteps=64)


def test_the_shipped_model_acts_as_its_sb3_zip_did() -> None:
    safe = load("dagger-student")
    legacy = load(MODELS_DIR / "dagger-student" / "model.zip", trust_pickle=True)
    env = make_env(safe, "random", {"physics": "kinematic"})
    obs, _ = env.reset(seed=11)
    for t in range(150):
        action, _ = safe.predict(obs)
        np.testing.assert_array_equal(action, legacy.predict(obs)[0])
        obs, _, terminated, truncated, _ = env.step(action)
        if terminated or truncated:
            obs, _ = env.reset(seed=100 + t)
    batch = {k: np.stack([v, v]) for k, v in obs.items()}
    np.testing.assert_array_equal(safe.predict(batch)[0], legacy.predict(batch)[0])


def test_an_sb3_model_saved_with_save_model_dir_loads(tmp_path: Path) -> None:
    from stable_baselines3 import PPO

    from radial_ibvs_agents import make_vec_env

    kwargs = {"physics": "kinematic", "scenario": "paper-lab"}
    venv = make_vec_env("RadialIBVS/Parking-v0", 2, seed=0, **kwargs)
    model = PPO(
        "MultiInputPolicy", venv, n_steps=16, batch_size=32, policy_kwargs={"net_arch": [8]}
    )
    save_model_dir(model, tmp_path / "mine", env_id="RadialIBVS/Parking-v0", env_kwargs=kwargs)
    policy = load(tmp_path / "mine")
    obs, _ = gym.make("RadialIBVS/Parking-v0", **kwargs).reset(seed=0)
    expected, _ = model.predict(obs, deterministic=True)
    np.testing.assert_array_equal(policy.predict(obs)[0], expected)


def test_save_model_dir_reads_the_env_and_its_normalisation_from_the_model(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from stable_baselines3 import PPO
    from stable_baselines3.common.env_util import make_vec_env as sb3_make_vec_env
    from stable_baselines3.common.vec_env import VecNormalize

    from radial_ibvs_agents import make_vec_env, save_model_dir
    from radial_ibvs_agents.learned.files.saving import env_spec_of

    kwargs = {"physics": "kinematic", "scenario": "paper-sim", "task": 2}
    venv = VecNormalize(make_vec_env("RadialIBVS/Parking-v0", 2, seed=0, **kwargs))
    model = PPO(
        "MultiInputPolicy", venv, n_steps=16, batch_size=32, policy_kwargs={"net_arch": [8]}
    )
    model.learn(32)
    save_model_dir(model, tmp_path / "mine")  # nothing typed again
    meta = json.loads((tmp_path / "mine" / "metadata.json").read_text())
    assert meta["env_id"] == "RadialIBVS/Parking-v0" and meta["env_kwargs"] == kwargs
    assert (tmp_path / "mine" / "normalization.npz").is_file()
    policy = load(tmp_path / "mine")
    obs, _ = gym.make("RadialIBVS/Parking-v0", **kwargs).reset(seed=0)
    normalised = venv.normalize_obs({k: v[None] for k, v in obs.items()})
    expected, _ = model.predict(normalised, deterministic=True)
    np.testing.assert_allclose(policy.predict(obs)[0], expected[0], atol=1e-6)  # float32 stats
    argv = ["evaluate", "--policy", str(tmp_path / "mine"), "--scenario", "paper-sim"]
    assert main([*argv, "--episodes", "1"]) == 0
    # SB3's own make_vec_env over gym.make, and a plain env
    dummy = sb3_make_vec_env("RadialIBVS/ParkingGoal-v1", 2, env_kwargs={"physics": "kinematic"})
    assert env_spec_of(dummy) == ("RadialIBVS/ParkingGoal-v1", {"physics": "kinematic"})
    plain = gym.wrappers.FlattenObservation(gym.make("RadialIBVS/Parking-v0", task=1))
    assert env_spec_of(plain) == ("RadialIBVS/Parking-v0", {"task": 1})
    with pytest.raises(ValueError, match="'CartPole-v1' is not an env of radial_ibvs_gym"):
        env_spec_of(gym.make("CartPole-v1"))


def test_trust_model_loads_a_folder_holding_only_an_sb3_zip(tmp_path: Path) -> None:
    """What --help says: a stable-baselines3 model.zip, saved by SB3 itself, when trusted."""
    from stable_baselines3 import PPO

    from radial_ibvs_agents import make_vec_env

    venv = make_vec_env("RadialIBVS/Parking-v0", 2, seed=0, physics="kinematic")
    model = PPO(
        "MultiInputPolicy", venv, n_steps=16, batch_size=32, policy_kwargs={"net_arch": [8]}
    )
    (tmp_path / "sb3").mkdir()
    model.save(tmp_path / "sb3" / "model.zip")
    with pytest.raises(ValueError, match="refusing"):
        load(tmp_path / "sb3")
    policy = load(tmp_path / "sb3", trust_pickle=True)
    assert policy.metadata["algo"] == "ppo" and policy.env_id == "RadialIBVS/Parking-v0"
    argv = ["evaluate", "--policy", str(tmp_path / "sb3"), "--trust-model", "--episodes", "1"]
    assert main([*argv, "--scenario", "paper-sim", "--env-kwarg", "physics=kinematic"]) == 0


def test_altered_or_hostile_descriptions_are_refused(tmp_path: Path) -> None:
    model = tmp_path / "m"
    shutil.copytree(MODELS_DIR / "dagger-student", model)
    described = json.loads((model / DESCRIPTION).read_text())

    def write(**changes: object) -> None:
        (model / DESCRIPTION).write_text(json.dumps({**described, **changes}))

    write(policy_class={"__class__": "os.system"})
    with pytest.raises(ValueError, match="not allowed"):
        load_policy(model)
    kwargs = {**described["policy_kwargs"], "activation_fn": {"__class__": "builtins.eval"}}
    write(policy_kwargs=kwargs)
    with pytest.raises(ValueError, match="not allowed"):
        load_policy(model)
    write(format_version=99)
    with pytest.raises(ValueError, match="format_version"):
        load_policy(model)
    write(weights_sha256="0" * 64)
    with pytest.raises(ValueError, match="SHA-256"):
        load(model)
    (model / DESCRIPTION).write_text("{not json")
    with pytest.raises(ValueError, match="corrupt"):
        load(model)
    write()
    (model / WEIGHTS).write_bytes(b"\0" * 64)
    with pytest.raises(ValueError, match="SHA-256"):
        load(model)


def test_spaces_round_trip_through_json() -> None:
    env = gym.make("RadialIBVS/Parking-v0", physics="kinematic")
    for space in (env.observation_space, env.action_space, gym.spaces.Discrete(3, start=1)):
        text = json.dumps(space_to_json(space), allow_nan=False)
        assert space_from_json(json.loads(text)) == space
    with pytest.raises(ValueError, match="unknown space type"):
        space_from_json({"type": "Tuple"})


def test_a_pickled_weights_file_is_a_value_error_even_when_trusted(tmp_path: Path) -> None:
    legacy = tmp_path / "legacy"
    legacy.mkdir()
    for name in ("model.zip", "metadata.json", "normalization.npz"):
        shutil.copy(MODELS_DIR / "dagger-student" / name, legacy / name)
    marker = tmp_path / "marker"
    poison_zip(legacy / "model.zip", marker, member="policy.pth")
    with pytest.raises(ValueError, match="corrupt"):
        load(legacy, trust_pickle=True)  # torch's weights-only reader refuses the pickle
    assert not marker.exists()


def test_models_saved_before_the_moves_load_by_the_table_of_former_paths() -> None:
    # a student saved when the extractors were agents.learned.extractors (tests/_support/models)
    folder = Path(__file__).resolve().parents[2] / "_support" / "models" / "saved-before-the-rename"
    former = "agents.learned.extractors.LandmarkPoseExtractor"
    assert former in (folder / "policy.json").read_text()
    current = "radial_ibvs_agents.learned.networks.extractors.LandmarkPoseExtractor"
    assert current_name(former) == current
    safe = load(folder)
    extractor = safe.model.features_extractor
    assert type(extractor).__module__ == "radial_ibvs_agents.learned.networks.extractors"
    # a trusted model.zip: its pickles import the former module path, for the load only
    legacy = load(folder / "model.zip", trust_pickle=True)
    assert type(legacy.model.policy.features_extractor) is type(extractor)
    assert "agents" not in sys.modules and "agents.learned.extractors" not in sys.modules
    obs = {k: v.sample() for k, v in safe.model.observation_space.spaces.items()}
    np.testing.assert_array_equal(safe.predict(obs)[0], legacy.predict(obs)[0])


def test_every_former_module_path_names_a_current_module() -> None:
    import importlib

    for former in [*FORMER_MODULES, "agents", "agents.learned", "agents.analytic.ibvs_policy"]:
        importlib.import_module(current_module(former))
    assert current_module("agents.learned.extractors") == (
        "radial_ibvs_agents.learned.networks.extractors"
    )
    assert current_name("torch.nn.modules.activation.ReLU") == "torch.nn.modules.activation.ReLU"
    assert current_name("agentsx.Y") == "agentsx.Y"
