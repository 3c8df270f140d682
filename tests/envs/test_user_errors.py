"""A new user's frictions, each fixed: typos, missing files, out-of-range actions."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

import radial_ibvs_gym  # noqa: F401
from radial_ibvs_gym.config import ConfigError
from radial_ibvs_gym.envs.rules import ACTION_RULE


def test_a_typo_of_an_env_argument_is_named_as_such_with_a_suggestion() -> None:
    typo = r"argument 'phisics' \(did you mean 'physics'\?\)"
    with pytest.raises(ValueError, match=typo) as caught:
        gym.make("RadialIBVS/Parking-v0", phisics="kinematic")
    assert "the env's arguments" in str(caught.value) and "'obs_mode'" in str(caught.value)
    with pytest.raises(ValueError, match=r"did you mean 'depth_scale'"):
        gym.make("RadialIBVS/Parking-v0", depth_scal=1.3)
    with pytest.raises(ValueError, match=r"did you mean 'goal_depths'"):
        gym.make("RadialIBVS/ParkingGoal-v1", goal_depth=True)


def test_scenario_names_and_missing_files_are_named_with_the_shipped_ones(tmp_path) -> None:
    with pytest.raises(ConfigError, match=r"'paper-simm' \(did you mean 'paper-sim'\?\)"):
        gym.make("RadialIBVS/Parking-v0", scenario="paper-simm")
    with pytest.raises(ConfigError, match=r"not found.*'paper-lab'"):
        gym.make("RadialIBVS/Parking-v0", scenario=str(tmp_path / "paper-lb.yaml"))


def test_out_of_range_actions_are_clipped_alike_in_scalar_and_vector_envs() -> None:
    kwargs = dict(scenario="paper-lab", physics="kinematic")
    wild, edge = np.array([5.0, -7.0], dtype=np.float32), np.array([1.0, -1.0], dtype=np.float32)
    a, b = gym.make("RadialIBVS/Parking-v0", **kwargs), gym.make("RadialIBVS/Parking-v0", **kwargs)
    a.reset(seed=0)
    b.reset(seed=0)
    for _ in range(5):
        info_a = a.step(wild)[-1]
        info_b = b.step(edge)[-1]
        np.testing.assert_array_equal(info_a["robot_pose"], info_b["robot_pose"])
    mode = "vector_entry_point"
    venv = gym.make_vec("RadialIBVS/Parking-v0", num_envs=2, vectorization_mode=mode, **kwargs)
    venv.reset(seed=0)
    info = venv.step(np.stack([wild, edge]))[-1]
    assert not np.array_equal(info["robot_pose"][0], info["robot_pose"][1])  # different rooms
    venv.reset(seed=0)
    same = venv.step(np.stack([edge, edge]))[-1]
    np.testing.assert_array_equal(info["robot_pose"][0], same["robot_pose"][0])
    with pytest.raises(ValueError, match=rf"action must be {ACTION_RULE}".replace("(", r"\(")
                       .replace(")", r"\)").replace("[", r"\[").replace("]", r"\]")):  # fmt: skip
        a.step(np.array([np.nan, 0.0]))
    with pytest.raises(ValueError, match="env 1: action must be two finite real numbers"):
        venv.step(np.array([[0.0, 0.0], [np.inf, 0.0]]))
    with pytest.raises(ValueError, match="got an array of complex128"):
        venv.step(np.array([[0.1j, 0.0], [0.0, 0.0]]))
