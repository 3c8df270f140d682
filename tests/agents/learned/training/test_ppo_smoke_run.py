"""A smoke run of PPO through the CLI, and its model: the files it writes, loading it,
evaluating it, resuming and exporting it, and the errors that name a bad model."""

from __future__ import annotations

import contextlib
import io
import json
import shutil
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

import radial_ibvs_gym  # noqa: F401
from radial_ibvs_agents import make_policy
from radial_ibvs_agents.cli import main
from radial_ibvs_agents.learned import LearnedPolicy, load
from radial_ibvs_agents.learned.training.train import train
from radial_ibvs_agents.learned.training.zoo_config import load_train_config

CONFIG = Path(__file__).resolve().parents[4] / "configs" / "agents" / "ppo_parking.yaml"


@pytest.fixture(scope="module")
def trained(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A few hundred steps of PPO through the CLI (the smoke run CI can afford)."""
    out = tmp_path_factory.mktemp("train") / "ppo"
    argv = ["train", "--algo", "ppo", "--config", str(CONFIG), "--total-timesteps", "512"]
    argv += ["--out", str(out), "--seed", "3", "--no-progress", "--env-kwarg", "task=1"]
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        assert main(argv) == 0
    (out.parent / "stdout.txt").write_text(printed.getvalue())
    return out


def test_training_says_what_it_runs_before_it_starts(trained: Path) -> None:
    # without a terminal there is no bar: the first line says what runs and where it logs
    first = (trained.parent / "stdout.txt").read_text().splitlines()[0]
    assert first.startswith("training ppo on RadialIBVS/Parking-v0 for 512 steps with 8 envs")
    assert "logs/progress.csv" in first


def test_training_writes_a_loadable_model_directory(trained: Path) -> None:
    for name in ("policy.safetensors", "policy.json", "normalization.npz", "metadata.json"):
        assert (trained / name).is_file(), name
    assert (trained / "model.zip").is_file()  # for SB3 users and --resume
    assert not (trained / "vecnormalize.pkl").exists()  # no pickled statistics
    # shorter than eval_freq, the run still evaluates once and writes the documented files
    for name in ("best_model.zip", "learning_curve.png", "best/policy.safetensors"):
        assert (trained / name).is_file(), name
    metadata = json.loads((trained / "metadata.json").read_text())
    assert metadata["algo"] == "ppo" and metadata["seed"] == 3
    assert metadata["env_kwargs"]["task"] == 1
    assert metadata["total_timesteps"] >= 512
    assert len(metadata["learning_curve"]) >= 1
    assert "radial-ibvs train" in metadata["command"] and metadata["git_revision"]
    policy = load(trained)
    assert isinstance(policy, LearnedPolicy)
    env = gym.make("RadialIBVS/Parking-v0", **policy.env_kwargs)
    policy.check_observation_space(env.observation_space)
    obs, _ = env.reset(seed=0)
    action, _ = policy.predict(obs)
    assert action.shape == (2,) and env.action_space.contains(action)
    batch = {k: np.stack([v, v]) for k, v in obs.items()}
    actions, _ = policy.predict(batch)
    np.testing.assert_allclose(actions, [action, action], atol=1e-6)


def test_training_evaluations_count_success_at_the_three_tolerances(trained: Path) -> None:
    from radial_ibvs_agents.learned.training.tolerance_eval import (
        read_tolerance_curve,
        success_within,
    )

    curve = json.loads((trained / "metadata.json").read_text())["learning_curve"]
    rates = read_tolerance_curve(trained / "eval" / "tolerances.npz")
    assert [row["timesteps"] for row in curve] == sorted(rates)
    for row in curve:
        mine = rates[row["timesteps"]]
        assert mine["2cm/2deg"] == row["success_rate"]  # the env's own success, as SB3 counts
        assert row["success_rate"] <= row["success_10cm/5deg"] <= row["success_30cm/15deg"]
    near = {"is_success": False, "collision": False, "position_error_m": 0.05,
            "heading_error_deg": 4.0}  # fmt: skip
    assert success_within(near, 0.10, 5.0) and not success_within(near, 0.02, 2.0)
    assert not success_within({**near, "collision": True}, 0.30, 15.0)
    assert success_within({**near, "is_success": True, "collision": True}, 0.02, 2.0)


def test_learned_policy_matches_sb3_with_vecnormalize(trained: Path) -> None:
    # our plain-array normalisation must equal VecNormalize's, so the model sees the same input
    from stable_baselines3 import PPO
    from stable_baselines3.common.env_util import make_vec_env
    from stable_baselines3.common.vec_env import VecNormalize

    from radial_ibvs_agents.learned.training.train import _restore_normalization

    policy = load(trained)
    venv = make_vec_env("RadialIBVS/Parking-v0", n_envs=1, env_kwargs=policy.env_kwargs)
    venv = VecNormalize(venv, training=False, norm_reward=False)
    _restore_normalization(venv, trained / "normalization.npz", default_count=1)
    obs = venv.reset()
    expected, _ = PPO.load(trained / "model.zip").predict(obs, deterministic=True)
    raw = venv.get_original_obs()
    ours, _ = policy.predict(raw)
    np.testing.assert_allclose(ours, expected, atol=1e-5)


def test_training_resumes_from_its_checkpoint(trained: Path, tmp_path: Path) -> None:
    config = load_train_config(CONFIG)
    config = type(config)(
        **{**config.__dict__, "n_envs": 2, "env_kwargs": {**config.env_kwargs, "task": 1}}
    )
    out = train(config, tmp_path / "more", resume=trained, total_timesteps=256, progress=False)
    metadata = json.loads((out / "metadata.json").read_text())
    assert (
        metadata["total_timesteps"]
        > json.loads((trained / "metadata.json").read_text())["total_timesteps"]
    )


def test_evaluate_cli_runs_a_learned_model_and_writes_rows(
    trained: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    rows_path = tmp_path / "rows.json"
    argv = ["evaluate", "--policy", str(trained), "--episodes", "2", "--task", "1"]
    assert main([*argv, "--env-kwarg", "physics=kinematic", "--json", str(rows_path)]) == 0
    rows = json.loads(rows_path.read_text())
    assert len(rows) == 2 and {r["seed"] for r in rows} == {0, 1}
    assert "episodes" in capsys.readouterr().out


def test_a_model_on_a_different_observation_space_is_refused(trained: Path) -> None:
    policy = load(trained)
    env = gym.make("RadialIBVS/Parking-v0", obs_mode="points")
    with pytest.raises(ValueError, match="lacks"):
        policy.check_observation_space(env.observation_space)
    env = gym.make("RadialIBVS/Parking-v0", scenario="paper-lab", obs_mode="features")
    with pytest.raises(ValueError, match="shape"):
        policy.check_observation_space(env.observation_space)


def test_missing_corrupt_and_unknown_models_are_named(trained: Path, tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="unknown policy 'ppo-nowhere'"):
        make_policy("ppo-nowhere")
    empty = tmp_path / "empty"
    empty.mkdir()
    with pytest.raises(ValueError, match=r"metadata\.json is missing"):
        load(empty)
    (empty / "metadata.json").write_text((trained / "metadata.json").read_text())
    with pytest.raises(ValueError, match=r"policy\.safetensors and .*policy\.json are missing"):
        load(empty)
    broken = tmp_path / "broken"
    broken.mkdir()
    (broken / "model.zip").write_bytes(b"not a zip")
    (broken / "metadata.json").write_text((trained / "metadata.json").read_text())
    with pytest.raises(ValueError, match="corrupt"):
        load(broken, trust_pickle=True)
    shutil.copytree(trained, broken, dirs_exist_ok=True)
    (broken / "policy.safetensors").write_bytes(b"not tensors")
    with pytest.raises(ValueError, match="SHA-256"):
        load(broken)
    (broken / "metadata.json").write_text("{not json")
    with pytest.raises(ValueError, match="corrupt"):
        load(broken)


def test_benchmark_skips_a_model_whose_observations_do_not_fit_the_suite(trained: Path) -> None:
    from radial_ibvs_agents.experiments.jobs import Job, run_job
    from radial_ibvs_agents.experiments.suites import Variant

    lab = Variant("lab", "9 beacons", "paper-lab", {"physics": "kinematic"}, 2, False)
    result = run_job(Job(str(trained), lab, 2))
    assert result.skipped is not None and "shape" in result.skipped and not result.rows


def test_export_keeps_a_small_loadable_model_directory(trained: Path, tmp_path: Path) -> None:
    from radial_ibvs_agents.learned.training.train import export_model

    dest = export_model(trained, tmp_path / "ppo-test")
    names = {p.name for p in dest.iterdir()}
    assert {"policy.safetensors", "policy.json", "metadata.json", "normalization.npz"} <= names
    assert "vecnormalize.pkl" not in names and "checkpoints" not in names  # no pickles, no bulk
    assert json.loads((dest / "metadata.json").read_text())["shipped"]
    obs, _ = gym.make("RadialIBVS/Parking-v0", **load(dest).env_kwargs).reset(seed=0)
    assert load(dest).predict(obs)[0].shape == (2,)
