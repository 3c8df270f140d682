"""The env a policy runs in: a named scenario replaces the world a model was trained in."""

from __future__ import annotations

from typing import Any

import numpy as np

from radial_ibvs_agents.rollouts import env_kwargs_for, make_env
from radial_ibvs_agents.rollouts.envs import WORLD_KEYS


class _Trained:
    """A policy whose training env drew cameras and scenes from ranges (domain randomisation)."""

    env_kwargs: dict[str, Any] = {  # noqa: RUF012
        "scenario": "random",
        "physics": "kinematic",
        "obs_mode": "features",
        "goal_depths": True,
        "max_landmarks": 16,
        "camera": {
            "mirror": "A",
            "non_central_offset": 0.01,
            "imperfection_ranges": {"pixel_noise_std": [0.5, 1.0]},
        },
        "goal_image_frames": 30,
        "random_landmarks": {"count": [5, 9], "height": [0.2, 2.4]},
        "camera_height": [1.7, 2.1],
        "mirrors": ["A", "B"],
        "start_reach": 0.3,
    }

    def predict(self, obs: Any, state: Any = None, episode_start: Any = None) -> Any:
        return np.zeros(2, np.float32), state


def test_a_named_scenario_replaces_the_training_world_and_keeps_how_the_model_sees() -> None:
    policy = _Trained()
    kwargs = env_kwargs_for(policy, "paper-lab", {"physics": "pymunk"})
    assert kwargs == {
        "scenario": "paper-lab",
        "physics": "pymunk",
        "obs_mode": "features",
        "goal_depths": True,
        "max_landmarks": 16,
    }
    assert set(policy.env_kwargs) - set(kwargs) <= WORLD_KEYS
    # the paper's lab takes it: its fixed landmarks do not meet the model's drawn ones
    env = make_env(policy, "paper-lab", {"physics": "kinematic"})
    env.reset(seed=0)
    assert not env.unwrapped.config.scenario.config.camera.imperfections.any
    # without a scenario the model runs in its own world, and a caller's keywords still win
    own = env_kwargs_for(policy, None, {"goal_image_frames": 1})
    assert own["camera_height"] == [1.7, 2.1] and own["goal_image_frames"] == 1
