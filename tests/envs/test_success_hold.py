"""``success_hold_steps``: success asks the pose held within the tolerances, not passed."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

import radial_ibvs_gym  # noqa: F401  (registers the ids)
from radial_ibvs_agents import make_policy


def test_success_hold_steps_needs_the_pose_held_a_pass_does_not_count() -> None:
    from radial_ibvs_gym.envs import rules

    kwargs = {
        "success_position_m": 0.02,
        "success_heading_rad": 0.05,
        "min_visible": 3,
        "terminate_on_collision": True,
    }
    held = np.zeros(3, dtype=np.int64)
    errors = [(0.01, 0.01), (0.01, 0.01), (0.5, 0.01)]  # two in, then out: a pass
    outcomes = []
    for e_p, e_h in errors:
        success, _, terminated, held = rules.episode_end(
            np.full(3, e_p), np.full(3, e_h), np.full(3, 8), np.zeros(3, bool),
            held=held, hold_steps=3, **kwargs,
        )  # fmt: skip
        assert (terminated == success).all()
        outcomes.append((bool(success[0]), int(held[0])))
    assert outcomes == [(False, 1), (False, 2), (False, 0)]
    success, *_ = rules.episode_end(0.01, 0.01, 8, False, held=2, hold_steps=3, **kwargs)
    assert success  # the third step in a row


@pytest.mark.parametrize("physics", ["kinematic", "pymunk"])
def test_a_policy_that_stops_at_the_goal_succeeds_the_hold_later_scalar_and_batched(
    physics: str,
) -> None:
    policy = make_policy("ibvs-straight")
    kwargs = {"scenario": "random", "physics": physics, **policy.env_kwargs}
    lengths = {}
    for hold in (1, 10):
        env = gym.make("RadialIBVS/Parking-v0", success_hold_steps=hold, **kwargs)
        obs, _ = env.reset(seed=0)
        steps, done = 0, False
        while not done:
            action, _ = policy.predict(obs)
            obs, _, terminated, truncated, info = env.step(action)
            steps, done = steps + 1, terminated or truncated
        assert info["is_success"]
        lengths[hold] = steps
        env.close()
    assert lengths[10] == lengths[1] + 9  # it stayed: the 10th step in a row within them
    if physics == "kinematic":  # the vector env counts the same way
        venv = gym.make_vec(
            "RadialIBVS/Parking-v0", num_envs=2, vectorization_mode="vector_entry_point",
            autoreset_mode="disabled", success_hold_steps=10, **kwargs,
        )  # fmt: skip
        obs, _ = venv.reset(seed=[0, 1])
        for _ in range(lengths[10]):
            action, _ = policy.predict(obs)
            obs, _, terminated, _, info = venv.step(action)
        assert terminated[0] and info["is_success"][0]


@pytest.mark.parametrize("value", [0, 601, 2.5, True])
def test_bad_success_hold_steps_are_named(value: object) -> None:
    with pytest.raises(ValueError, match="success_hold_steps"):
        gym.make("RadialIBVS/Parking-v0", success_hold_steps=value)
