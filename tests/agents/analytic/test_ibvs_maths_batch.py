"""The batched IBVS (radial_ibvs_agents.analytic.ibvs_maths_batch) against the one-robot-at-a-time
policy."""

from __future__ import annotations

import numpy as np
import pytest

from radial_ibvs_agents.analytic.ibvs_policy import IBVSPolicy
from radial_ibvs_agents.learned.training.sb3_vec_env import make_vec_env


def _observations(n_envs: int = 32, steps: int = 60, seed: int = 3) -> list[dict[str, np.ndarray]]:
    """Batches of observations along IBVS-driven episodes in random rooms (16 slots)."""
    venv = make_vec_env(
        "RadialIBVS/Parking-v0", n_envs, seed=seed, scenario="random", physics="kinematic",
        goal_depths=True, max_landmarks=16,
    )  # fmt: skip
    policy = IBVSPolicy(allow_backward=True)
    rng = np.random.default_rng(seed)
    obs, batches = venv.reset(), []
    for _ in range(steps):
        batches.append({k: v.copy() for k, v in obs.items()})
        action = np.array([policy._act({k: v[i] for k, v in obs.items()}) for i in range(n_envs)])
        action += rng.normal(0.0, 0.3, action.shape)  # wander off the IBVS path a little
        obs, *_ = venv.step(np.clip(action, -1, 1).astype(np.float32))
    return batches


@pytest.fixture(scope="module")
def batches() -> list[dict[str, np.ndarray]]:
    return _observations()


@pytest.mark.parametrize("variant", ["paper", "no-frame-change"])
@pytest.mark.parametrize("allow_backward", [False, True])
def test_batch_equals_one_at_a_time(batches, variant, allow_backward):
    policy = IBVSPolicy(variant, allow_backward=allow_backward)
    for obs in batches:
        batched, _ = policy.predict(obs)
        rows = np.array(
            [policy._act({k: v[i] for k, v in obs.items()}) for i in range(len(obs["points"]))]
        )
        np.testing.assert_allclose(batched, rows, atol=2e-5)


def test_few_landmarks_give_zero_command(batches):
    obs = {k: v[:4].copy() for k, v in batches[10].items()}
    obs["visible"][0] = 0.0  # nothing seen
    obs["visible"][1, :] = 0.0
    obs["visible"][1, :2] = 1.0  # two landmarks: no estimate
    action, _ = IBVSPolicy().predict(obs)
    np.testing.assert_array_equal(action[:2], 0.0)
    rows = np.array([IBVSPolicy()._act({k: v[i] for k, v in obs.items()}) for i in range(4)])
    np.testing.assert_allclose(action, rows, atol=2e-5)


def test_degenerate_goal_image_gives_zero_command(batches):
    obs = {k: v[:2].copy() for k, v in batches[0].items()}
    goal = obs["goal_points"].reshape(2, -1, 2)
    goal[0] = np.where(np.hypot(goal[0, :, :1], goal[0, :, 1:]) > 0.5, [0.0, 1.0], 0.0)
    obs["goal_points"] = goal.reshape(2, -1)  # row 0: every goal point on one ray
    action, _ = IBVSPolicy().predict(obs)
    np.testing.assert_array_equal(action[0], 0.0)
    assert np.all(np.isfinite(action))


def test_goal_cache_gives_the_uncached_result_exactly(batches):
    """The per-episode goal terms change nothing: the same bits as computing them every step."""
    from dataclasses import fields

    from radial_ibvs_agents.analytic.ibvs_maths_batch import GoalCache, GoalTerms, ibvs_twist_batch

    cache = GoalCache()
    rng = np.random.default_rng(0)
    hidden_rows = 0
    for obs in batches:
        obs = {k: v.copy() for k, v in obs.items()}
        obs["visible"][rng.random(obs["visible"].shape) < 0.1] = 0.0  # some landmarks hidden
        args = (obs["points"], obs["goal_points"], obs["goal_depths"], obs["visible"])
        terms = cache.terms(obs["goal_points"], obs["goal_depths"])
        fresh = GoalTerms.of(obs["goal_points"], obs["goal_depths"])
        for f in fields(fresh):
            np.testing.assert_array_equal(getattr(terms, f.name), getattr(fresh, f.name))
        cached, plain = ibvs_twist_batch(*args, goal=terms), ibvs_twist_batch(*args)
        for a, b in zip(cached, plain, strict=True):
            np.testing.assert_array_equal(a, b)
        hidden_rows += int(np.any((obs["visible"] < 0.5) & terms.seen, axis=1).sum())
        small = cache.terms(obs["goal_points"][:3], obs["goal_depths"][:3])  # a second size
        np.testing.assert_array_equal(small.normal, fresh.normal[:3])
    assert hidden_rows > 100  # the path of the steps with landmarks out of view ran


def test_goal_cache_recomputes_a_changed_goal_only(batches):
    from radial_ibvs_agents.analytic.ibvs_maths_batch import GoalCache, GoalTerms

    obs = batches[0]
    cache = GoalCache()
    first = cache.terms(obs["goal_points"], obs["goal_depths"])
    before = first.normal.copy()
    goal_points, goal_depths = obs["goal_points"].copy(), obs["goal_depths"].copy()
    goal_points[5], goal_depths[5] = batches[-1]["goal_points"][7], batches[-1]["goal_depths"][7]
    again = cache.terms(goal_points, goal_depths)
    assert again is first  # updated in place
    expected = GoalTerms.of(goal_points[5:6], goal_depths[5:6])
    np.testing.assert_array_equal(again.normal[5], expected.normal[0])
    np.testing.assert_array_equal(np.delete(again.normal, 5, 0), np.delete(before, 5, 0))
    assert not np.array_equal(again.normal[5], before[5])
