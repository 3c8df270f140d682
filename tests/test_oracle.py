from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest
from stable_baselines3.common.env_util import make_vec_env
from stable_baselines3.common.evaluation import evaluate_policy

import radial_ibvs_gym  # noqa: F401
from agents import PoseOracle


@pytest.mark.parametrize("task", range(4))
def test_oracle_parks_on_the_paper_tasks(task: int) -> None:
    env = gym.make("RadialIBVS/Parking-v0", task=task, physics="kinematic", privileged=True)
    oracle = PoseOracle()
    obs, _ = env.reset(seed=0)
    for _ in range(600):
        action, _ = oracle.predict(obs)
        obs, _, terminated, truncated, info = env.step(action)
        if terminated or truncated:
            break
    assert info["is_success"]  # 2 cm / 2 deg at control_dt = 0.1 s
    assert info["n_visible"] == 8 and not info["collision"]


def test_oracle_runs_under_sb3_evaluate_policy_batched() -> None:
    venv = make_vec_env(
        "RadialIBVS/Parking-v0",
        n_envs=2,
        seed=0,
        env_kwargs={"physics": "kinematic", "privileged": True, "task": 1},
    )
    mean, _ = evaluate_policy(PoseOracle(), venv, n_eval_episodes=2)
    assert mean > 0  # progress towards the goal dominates the time penalty


def test_oracle_needs_the_privileged_observation() -> None:
    env = gym.make("RadialIBVS/Parking-v0")
    obs, _ = env.reset(seed=0)
    with pytest.raises(KeyError, match="privileged=True"):
        PoseOracle().predict(obs)


def test_oracle_stops_at_the_goal() -> None:
    obs = {"robot_pose": np.array([1.0, 2.0, 0.3]), "goal_pose": np.array([1.0, 2.001, 0.3])}
    action, state = PoseOracle().predict(obs)
    assert action.shape == (2,) and not action.any() and state is None


def test_oracle_with_nav2_speeds_drives_towards_the_goal() -> None:
    from agents import SmoothControlLaw

    oracle = PoseOracle(law=SmoothControlLaw())
    obs = {"robot_pose": np.array([0.0, 0.0, 0.0]), "goal_pose": np.array([2.0, 0.0, 0.0])}
    action, _ = oracle.predict(obs)
    assert action[0] == pytest.approx(1.0) and action[1] == pytest.approx(0.0)  # straight on
