"""Training's config, in the rl-zoo3 format (``radial_ibvs_agents.learned.training.zoo_config``),
and a short PPO run with the student's pose layer. The smoke run of PPO and its model are tested in
``training/test_ppo_smoke_run.py``."""

from __future__ import annotations

import json
import os
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

import radial_ibvs_gym  # noqa: F401
from radial_ibvs_agents.learned import load
from radial_ibvs_agents.learned.training.train import train
from radial_ibvs_agents.learned.training.zoo_config import load_train_config, parse_kwargs_string

CONFIG = Path(__file__).resolve().parents[3] / "configs" / "agents" / "ppo_parking.yaml"


def test_shipped_config_is_valid_rl_zoo3_format() -> None:
    config = load_train_config(CONFIG)
    assert config.env_id == "RadialIBVS/Parking-v0"
    assert config.policy == "MultiInputPolicy" and config.n_envs >= 1
    assert config.policy_kwargs["net_arch"] == [256, 256]
    assert config.normalize is not None and config.normalize["norm_obs"] is True
    assert config.env_kwargs["scenario"] == "paper-sim"
    gym.make(config.env_id, **config.env_kwargs)  # the env arguments are valid


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("dict(net_arch=[64, 64], activation_fn=nn.Nope)", "nn.Nope is not an activation"),
        ("dict(x=__import__('os'))", "only literals"),
        ("list(1, 2)", "expected 'dict"),
        ("dict(", "cannot parse"),
    ],
)
def test_zoo_strings_are_parsed_safely(text: str, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        parse_kwargs_string(text, "test")


def test_zoo_strings_accept_literals_and_activations() -> None:
    from torch import nn

    out = parse_kwargs_string("dict(net_arch=dict(pi=[64], vf=[64]), activation_fn=nn.ReLU)", "t")
    assert out == {"net_arch": {"pi": [64], "vf": [64]}, "activation_fn": nn.ReLU}


def test_bad_config_values_are_named(tmp_path: Path) -> None:
    path = tmp_path / "bad.yaml"
    path.write_text("RadialIBVS/Parking-v0:\n  n_envs: 0\n")
    with pytest.raises(ValueError, match="n_envs must be a positive integer"):
        load_train_config(path)
    path.write_text("RadialIBVS/Parking-v0: {}\nradial_ibvs_gym:\n  evalfreq: 3\n")
    with pytest.raises(ValueError, match="unknown key"):
        load_train_config(path)
    with pytest.raises(ValueError, match="'CartPole-v1' is not an env of radial_ibvs_gym"):
        load_train_config(CONFIG, "CartPole-v1")
    with pytest.raises(ValueError, match="no section for env id"):
        load_train_config(CONFIG, "RadialIBVS/ParkingImage-v0")
    # a section named "module:EnvId" would make gym.make import the module: refused by name
    path.write_text("this:RadialIBVS/Parking-v0: {}\n")
    with pytest.raises(ValueError, match=r"the section name: .* \(the 'module:' form imports"):
        load_train_config(path)
    with pytest.raises(ValueError, match="not found"):
        load_train_config(tmp_path / "missing.yaml")
    path.write_text("RadialIBVS/Parking-v0: {}\nradial_ibvs_gym:\n  extractor: mine.Net\n")
    with pytest.raises(ValueError, match=r"extractor must be one of .*got 'mine.Net'"):
        load_train_config(path)


def test_ppo_trains_with_the_students_pose_layer(tmp_path: Path) -> None:
    """``extractor: landmark_pose``: the student's extractor, its raw keys not normalised."""
    config = tmp_path / "pose.yaml"
    config.write_text(
        "base: "  # relative to this config, as a base must be: into the shipped configs
        + os.path.relpath(
            Path(__file__).resolve().parents[3] / "research/configs/ppo_pose_layer.yaml", tmp_path
        )
        + "\nRadialIBVS/Parking-v0: {n_envs: 4, n_steps: 16, batch_size: 32, n_epochs: 1}\n"
        + "radial_ibvs_gym: {eval_episodes: 1, eval_freq: 64}\n"
    )
    out = train(load_train_config(config), tmp_path / "model", total_timesteps=64, progress=False)
    policy = load(out)
    assert type(policy.model.features_extractor).__name__ == "LandmarkPoseExtractor"
    with np.load(out / "normalization.npz") as saved:
        normalised = {name.split("/", 1)[1] for name in saved.files if "/" in name}
    assert normalised == {"landmark_mask"}  # the rest is read raw, as the student's
    metadata = json.loads((out / "metadata.json").read_text())
    assert metadata["extractor"] == "landmark_pose"
