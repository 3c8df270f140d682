"""The learned policies' own ``predict`` path gives stable-baselines3's actions, bit for bit."""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np
import pytest

import radial_ibvs_gym  # noqa: F401  (registers the environments)
from radial_ibvs_agents.learned.files.loading import LearnedPolicy, load
from radial_ibvs_agents.learned.networks.residual import BASE_KEY, ResidualPolicy


def _observations(policy: Any, n: int, seed: int) -> list[dict[str, np.ndarray]]:
    """``n`` observations the network gets along an episode of random actions, resets included.

    A residual policy's network also gets the base policy's action (``base_action``).
    """
    env = gym.make("RadialIBVS/Parking-v0", **policy.env_kwargs)
    env.action_space.seed(seed)
    obs, _ = env.reset(seed=seed)
    out = []
    for _ in range(n):
        if isinstance(policy, ResidualPolicy):
            out.append({**obs, BASE_KEY: np.asarray(policy.base.predict(obs)[0], np.float32)})
        else:
            out.append(obs)
        obs, _, terminated, truncated, _ = env.step(env.action_space.sample())
        if terminated or truncated:
            obs, _ = env.reset()
    return out


@pytest.mark.parametrize("name", ["dagger-student"])
def test_the_mean_action_is_stable_baselines3s_predict(name: str) -> None:
    policy = load(name)
    learned: LearnedPolicy = getattr(policy, "learned", policy)  # the residual's network
    observations = _observations(policy, 40, seed=3)
    for obs in observations:
        normalised = learned._normalise(obs)
        fast = learned._mean_action(normalised)
        assert fast is not None
        sb3, _ = learned.model.predict(normalised, deterministic=True)
        np.testing.assert_array_equal(fast, np.asarray(sb3, dtype=np.float32))
        assert fast.shape == learned.model.action_space.shape
    batch = {k: np.stack([o[k] for o in observations]) for k in observations[0]}
    normalised = learned._normalise(batch)
    sb3, _ = learned.model.predict(normalised, deterministic=True)
    fast = learned._mean_action(normalised)
    assert fast is not None and fast.shape == (40, *learned.model.action_space.shape)
    # one matrix product for the batch: the same floats as SB3's on the same batch
    np.testing.assert_array_equal(fast, np.asarray(sb3, dtype=np.float32))


def test_stochastic_calls_and_recurrent_state_go_through_stable_baselines3() -> None:
    policy = load("dagger-student")
    obs = _observations(policy, 1, seed=0)[0]
    calls = []
    model_predict = policy.model.predict

    def counting(*args, **kwargs):
        calls.append(kwargs.get("deterministic", args[3] if len(args) > 3 else None))
        return model_predict(*args, **kwargs)

    policy.model.predict = counting
    policy.predict(obs)  # deterministic, no state: the mean action, not SB3's predict
    assert calls == []
    policy.predict(obs, deterministic=False)
    assert calls == [False]


def test_a_wrongly_shaped_observation_gets_stable_baselines3s_error() -> None:
    policy = load("dagger-student")
    obs = _observations(policy, 1, seed=0)[0]
    bad = {**obs, "points": np.zeros(7, np.float32)}
    with pytest.raises(ValueError):
        policy.predict(bad)


def test_a_policy_that_changes_the_actors_path_goes_through_stable_baselines3() -> None:
    """A subclass with its own distribution (a recurrent policy's memory, say) is not bypassed."""
    policy = load("dagger-student")
    base = type(policy.model)

    class Custom(base):  # type: ignore[misc, valid-type]
        def get_distribution(self, obs):  # type: ignore[no-untyped-def]
            return super().get_distribution(obs)

    policy.model.__class__ = Custom
    assert policy._fast_path() is None
    obs = _observations(policy, 1, seed=0)[0]
    action, _ = policy.predict(obs)
    sb3, _ = policy.model.predict(policy._normalise(obs), deterministic=True)
    np.testing.assert_array_equal(action, np.asarray(sb3, dtype=np.float32))
