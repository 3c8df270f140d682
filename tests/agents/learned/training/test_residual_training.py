"""Training a residual policy, and the model it writes: a residual policy, exported with a gate."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import yaml

from radial_ibvs_agents.analytic.ibvs_policy import IBVSPolicy
from radial_ibvs_agents.learned import load
from radial_ibvs_agents.learned.networks.residual import ResidualConfig, ResidualPolicy
from radial_ibvs_agents.learned.training.train import export_model, train
from radial_ibvs_agents.learned.training.zoo_config import load_train_config

CONFIG = Path(__file__).resolve().parents[4] / "research" / "configs" / "ppo_residual.yaml"


def test_a_trained_residual_model_loads_as_a_residual_policy(tmp_path: Path) -> None:
    data = yaml.safe_load(CONFIG.read_text())
    section = data["RadialIBVS/Parking-v0"]
    section.update(n_envs=8, n_steps=16, batch_size=64, n_epochs=1)
    path = tmp_path / "residual.yaml"
    path.write_text(yaml.safe_dump(data))
    config = load_train_config(path)
    assert config.residual == ResidualConfig("ibvs-backward", 0.5)
    out = train(config, tmp_path / "model", total_timesteps=128, progress=False, command="test")
    assert json.loads((out / "metadata.json").read_text())["residual"] == config.residual.as_dict()
    policy = load(out)
    assert isinstance(policy, ResidualPolicy)
    import gymnasium as gym

    env = gym.make("RadialIBVS/Parking-v0", **policy.env_kwargs)
    policy.check_observation_space(env.observation_space)
    obs, _ = env.reset(seed=1)
    action, _ = policy.predict(obs)
    base, _ = IBVSPolicy(allow_backward=True).predict(obs)
    assert action.shape == (2,) and np.all(np.abs(action - base) <= 0.5 + 1e-6)
    shipped = export_model(out, tmp_path / "shipped", residual_gate=0.25, note="gate on val.")
    exported = load(shipped)
    assert exported.residual == ResidualConfig("ibvs-backward", 0.5, gate=0.25)
    assert exported.metadata["residual_trained"] == {"base": "ibvs-backward", "scale": 0.5}
    assert exported.metadata["export_note"] == "gate on val."
    assert (shipped / "model.zip").stat().st_size < 5 * 2**20
