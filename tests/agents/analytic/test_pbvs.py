"""Position-based visual servoing: the pose from the image, the oracle's law on it."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest
from bearing_scenes import distance_to_danger_circle as _distance_to_danger_circle
from bearing_scenes import scene as _scene  # the pose layer's scenes
from hypothesis import given, settings
from hypothesis import strategies as st

import radial_ibvs_gym  # noqa: F401  (registers the envs)
from radial_ibvs_agents import make_policy
from radial_ibvs_agents.analytic.pbvs import PBVSPolicy, solve_goal_pose
from radial_ibvs_agents.analytic.pose_oracle import PoseOracle
from radial_ibvs_agents.learned.networks import pose_layer
from radial_ibvs_agents.rollouts import make_env, run_episode
from radial_ibvs_gym.geometry import pose_in_frame

finite = st.floats(-3.0, 3.0, allow_nan=False)


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 10_000), st.integers(3, 16), finite, finite, st.floats(-3.1, 3.1))
def test_the_numpy_solve_is_the_pose_layers_and_exact_on_noise_free_bearings(
    seed: int, n: int, tx: float, ty: float, theta: float
) -> None:
    now, goal, depth, mask = _scene(seed, n, tx, ty, theta)
    pose, valid = solve_goal_pose(now.numpy(), goal.numpy(), depth.numpy(), mask.numpy())
    twin, twin_valid = pose_layer.solve_goal_pose(now, goal, depth, mask)
    assert valid.tolist() == twin_valid.tolist()
    np.testing.assert_allclose(pose, twin.numpy(), atol=1e-9)
    if valid[0] or _distance_to_danger_circle(seed, n, tx, ty, theta) >= 1e-3:
        assert valid[0]
        np.testing.assert_allclose(pose[0, :2], [tx, ty], atol=1e-6)
        error = np.arctan2(pose[0, 3], pose[0, 2]) - theta
        assert abs(np.angle(np.exp(1j * error))) < 1e-6


def test_on_an_ideal_camera_pbvs_acts_as_the_pose_oracle() -> None:
    pbvs, oracle = PBVSPolicy(), PoseOracle()
    env = gym.make(
        "RadialIBVS/Parking-v0", scenario="random", physics="kinematic", goal_depths=True,
        privileged=True,
    )  # fmt: skip
    for seed in range(5):
        obs, _ = env.reset(seed=seed)
        target, valid = pbvs.goal_pose({k: v[None] for k, v in obs.items()})
        assert valid[0]
        truth = pose_in_frame(obs["robot_pose"], obs["goal_pose"])
        np.testing.assert_allclose(target[0], truth, atol=1e-6)
        np.testing.assert_allclose(pbvs.predict(obs)[0], oracle.predict(obs)[0], atol=1e-5)


def test_pbvs_parks_the_papers_tasks_from_the_image_alone() -> None:
    policy = make_policy("pbvs")
    assert policy.env_kwargs == {"goal_depths": True}  # no map, no true pose
    env = make_env(policy, "paper-sim", {"physics": "kinematic"})
    for task in range(4):
        log = run_episode(policy, env, seed=0, options={"task": task})
        assert log.success, (task, log.info["position_error_m"], log.info["heading_error_deg"])


def test_batched_actions_are_each_robots_own() -> None:
    policy = PBVSPolicy()
    env = gym.make_vec("RadialIBVS/Parking-v0", num_envs=6, scenario="random", physics="kinematic",
                       goal_depths=True)  # fmt: skip
    obs, _ = env.reset(seed=3)
    batch, _ = policy.predict(obs)
    for i in range(6):
        alone, _ = policy.predict({k: v[i] for k, v in obs.items()})
        np.testing.assert_array_equal(batch[i], alone)


def test_too_few_landmarks_give_a_zero_command_and_missing_depths_are_named() -> None:
    policy = PBVSPolicy()
    obs = {
        "points": np.array([1.0, 0.0, 0.0, 1.0, 0.0, 0.0]),
        "goal_points": np.array([1.0, 0.0, 0.0, 1.0, 0.0, 0.0]),
        "visible": np.array([1.0, 1.0, 0.0]),
        "goal_depths": np.array([2.0, 3.0, 1.0]),
    }
    np.testing.assert_array_equal(policy.predict(obs)[0], [0.0, 0.0])
    with pytest.raises(KeyError, match="make the env with"):
        policy.predict({k: v for k, v in obs.items() if k != "goal_depths"})


def test_the_filter_on_noise_free_images_acts_as_pbvs_and_parks() -> None:
    from radial_ibvs_agents.analytic.pbvs_ekf import PBVSEKFPolicy

    ekf, pbvs = PBVSEKFPolicy(), PBVSPolicy()
    env = make_env(ekf, "paper-sim", {"physics": "kinematic"})
    for task in range(4):
        obs, _ = env.reset(seed=0, options={"task": task})
        state, start = None, np.array([True])
        for _ in range(600):
            action, state = ekf.predict(obs, state, start)
            start = np.array([False])
            np.testing.assert_allclose(action, pbvs.predict(obs)[0], atol=2e-3)
            obs, _, terminated, truncated, info = env.step(action)
            if terminated or truncated:
                break
        assert info["is_success"], task


def test_the_filter_predicts_the_goal_through_the_robots_own_motion() -> None:
    from radial_ibvs_agents.analytic.pbvs_ekf import PBVSEKFPolicy

    ekf = PBVSEKFPolicy()
    mean, cov, velocity = np.array([[2.0, 1.0, 0.3]]), ekf.init_cov[None].copy(), np.zeros((1, 2))
    started = np.array([True])
    mean, cov, velocity = ekf._predict(mean, cov, velocity, np.zeros((1, 2)), started)
    np.testing.assert_allclose(mean[0], [2.0, 1.0, 0.3])  # standing still: the goal stays
    for _ in range(30):  # full speed ahead: the goal comes closer, straight on
        mean, cov, velocity = ekf._predict(mean, cov, velocity, np.array([[1.0, 0.0]]), started)
    assert mean[0, 0] < 2.0 and mean[0, 1:] == pytest.approx([1.0, 0.3])
    assert np.all(np.linalg.eigvalsh(cov[0]) > np.linalg.eigvalsh(ekf.init_cov))  # less sure
    with pytest.raises(ValueError, match="bearing_std"):
        PBVSEKFPolicy(bearing_std=0.0)
