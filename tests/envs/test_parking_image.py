"""``RadialIBVS/ParkingImage-v0``: images as observations, for pixel-based RL."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import radial_ibvs_gym  # noqa: F401  (registers the envs)

ENV_ID = "RadialIBVS/ParkingImage-v0"


def test_passes_the_gymnasium_checker_and_matches_its_space() -> None:
    env = gym.make(ENV_ID, physics="kinematic")
    check_env(env.unwrapped)
    obs, info = env.reset(seed=0)
    assert env.observation_space.contains(obs)
    assert obs["image"].shape == (84, 84, 1) and obs["image"].dtype == np.uint8
    assert {"robot_pose", "is_success", "n_visible"} <= set(info)


def test_the_image_at_the_goal_pose_is_the_goal_image() -> None:
    env = gym.make(ENV_ID, scenario="paper-lab", physics="kinematic", image_size=64)
    obs, info = env.reset(seed=3)
    assert not np.array_equal(obs["image"], obs["goal_image"])
    obs, info = env.reset(seed=3, options={"start": info["goal_pose"]})
    np.testing.assert_array_equal(obs["image"], obs["goal_image"])
    # the image turns with the robot: a quarter turn rotates the picture, not the goal image
    turned = info["goal_pose"] + np.array([0.0, 0.0, np.pi / 2])
    obs2, _ = env.reset(seed=3, options={"start": turned})
    np.testing.assert_array_equal(obs2["goal_image"], obs["goal_image"])
    assert np.mean(obs2["image"] != obs["image"]) > 0.05


def test_same_seed_same_images_with_sensor_noise() -> None:
    runs = []
    for _ in range(2):
        env = gym.make(ENV_ID, physics="kinematic", image_noise=5.0, image_size=48)
        obs, _ = env.reset(seed=5)
        frames = [obs["image"]]
        for _ in range(5):
            obs, *_ = env.step(np.array([0.4, -0.2], np.float32))
            frames.append(obs["image"])
        runs.append(np.stack(frames))
    np.testing.assert_array_equal(runs[0], runs[1])


def test_point_observation_arguments_are_refused() -> None:
    with pytest.raises(ValueError, match="obs_mode"):
        gym.make(ENV_ID, obs_mode="features")
    with pytest.raises(ValueError, match="beacon_radius"):
        gym.make(ENV_ID, beacon_radius=-1.0)


def test_stable_baselines3_trains_a_cnn_policy_on_it() -> None:
    from stable_baselines3 import PPO

    env = gym.make(ENV_ID, physics="kinematic")
    model = PPO("MultiInputPolicy", env, n_steps=32, batch_size=32, n_epochs=1, seed=0)
    model.learn(total_timesteps=32)
    obs, _ = env.reset(seed=1)
    action, _ = model.predict(obs, deterministic=True)
    assert action.shape == (2,) and np.isfinite(action).all()
    assert "image" in model.policy.features_extractor.extractors  # a CNN on each image


def test_the_channels_layout_is_a_box_that_cnn_policy_and_image_wrappers_take() -> None:
    from stable_baselines3 import PPO

    kwargs = {"scenario": "paper-lab", "physics": "kinematic", "image_size": 64}
    layered = gym.make(ENV_ID, image_layout="channels", **kwargs)
    check_env(layered.unwrapped)
    obs, _ = layered.reset(seed=3)
    assert layered.observation_space == gym.spaces.Box(0, 255, (64, 64, 2), np.uint8)
    both, _ = gym.make(ENV_ID, **kwargs).reset(seed=3)  # the same images, as channels
    np.testing.assert_array_equal(obs[..., :1], both["image"])
    np.testing.assert_array_equal(obs[..., 1:], both["goal_image"])
    resized = gym.wrappers.ResizeObservation(layered, (36, 36))
    assert resized.reset(seed=0)[0].shape == (36, 36, 2)
    stacked = gym.wrappers.FrameStackObservation(resized, 2)
    assert stacked.reset(seed=0)[0].shape == (2, 36, 36, 2)
    model = PPO("CnnPolicy", resized, n_steps=16, batch_size=16, n_epochs=1, seed=0)
    model.learn(total_timesteps=16)
    assert model.predict(resized.reset(seed=1)[0], deterministic=True)[0].shape == (2,)
    with pytest.raises(ValueError, match="image_layout"):
        gym.make(ENV_ID, image_layout="planar")
