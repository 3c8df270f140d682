"""The small DAgger run the tests share (``radial_ibvs_agents.learned.dagger.distill``): its env and
its config, and the PPO config that fine-tunes a student
(``radial_ibvs_agents.learned.training.fine_tune``)."""

from __future__ import annotations

import json
from pathlib import Path

ENV = {
    "scenario": "random", "physics": "kinematic", "obs_mode": "features", "goal_depths": True,
    "max_landmarks": 16,
}  # fmt: skip

SMALL = f"""
dagger:
  env_kwargs: {json.dumps(ENV)}
  teacher_kwargs:
    {{goal_tolerance: 0.01, waypoint_tolerance: 0.1, hold_radius: 0.0, drive_gate: 0.35,
      reverse: false, final_radius: 0.3}}
  n_envs: 16
  rounds: 2
  steps_per_round: 1024
  updates_per_round: 20
  batch_size: 128
  dataset_size: 5000
  history: {{frames: 3}}
  eval_episodes: 4
"""


def fine_tune_config(tmp_path: Path, extra: str) -> object:
    from radial_ibvs_agents.learned.training.zoo_config import load_train_config

    path = tmp_path / "ppo.yaml"
    path.write_text(
        "RadialIBVS/Parking-v0:\n  n_envs: 4\n  policy: MultiInputPolicy\n"
        '  normalize: "dict(norm_obs=True, norm_reward=True, gamma=0.99)"\n'
        "  n_steps: 16\n  batch_size: 32\n  n_epochs: 2\n  learning_rate: 0.001\n"
        f"radial_ibvs_gym:\n  env_kwargs: {json.dumps(ENV)}\n  eval_freq: 1000000\n"
        f"  eval_episodes: 1\n{extra}"
    )
    return load_train_config(path)
