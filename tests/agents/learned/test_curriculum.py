"""The reverse curriculum: starts near the goal (``reach``), the envs' ``start_reach``, the
schedule and its config. Training with it (and with HER) is tested in
``training/test_curriculum_training.py``."""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import radial_ibvs_gym  # noqa: F401
from radial_ibvs_agents.learned.training.curriculum import CurriculumConfig
from radial_ibvs_agents.learned.training.sb3_vec_env import make_vec_env
from radial_ibvs_gym.geometry import wrap_angle
from radial_ibvs_gym.scenarios import load_scenario


@settings(max_examples=40, deadline=None)
@given(reach=st.floats(0.01, 0.99), seed=st.integers(0, 2**32 - 1))
def test_starts_lie_within_reach_of_the_goal(reach: float, seed: int) -> None:
    s = load_scenario("random-obstacles")
    c = s.config
    e = s.sample(np.random.default_rng(seed), reach=reach)
    distance = math.hypot(*(e.start[:2] - e.goal[:2]))
    assert reach * c.min_start_goal_distance - 1e-9 <= distance
    assert distance <= reach * c.max_start_goal_distance + 1e-9
    assert abs(wrap_angle(e.start[2] - e.goal[2])) <= reach * math.pi + 1e-9
    w, d = e.room
    m = c.wall_clearance
    assert m <= e.start[0] <= w - m and m <= e.start[1] <= d - m
    for ox, oy, r in e.obstacles:
        assert math.hypot(e.start[0] - ox, e.start[1] - oy) >= r + m
    assert s.visible(e.start, e.landmarks).sum() >= c.min_visible_at_goal


def test_full_reach_keeps_the_random_stream() -> None:
    s = load_scenario("random")
    a = s.sample(np.random.default_rng(5))
    b = s.sample(np.random.default_rng(5), reach=1.0)
    for x, y in zip(a, b, strict=True):
        np.testing.assert_array_equal(x, y)


def test_small_reach_starts_near_the_goal_on_average() -> None:
    s = load_scenario("random")
    rng = np.random.default_rng(0)
    near = [s.sample(rng, reach=0.1) for _ in range(50)]
    far = [s.sample(rng) for _ in range(50)]

    def mean_distance(episodes: list) -> float:
        return float(np.mean([math.hypot(*(e.start[:2] - e.goal[:2])) for e in episodes]))

    assert mean_distance(near) < 0.6 < 1.0 < mean_distance(far)


@pytest.mark.parametrize("bad", [0.0, -0.1, 1.5, math.nan, True, "0.5"])
def test_bad_reach_is_named(bad: object) -> None:
    s = load_scenario("random")
    with pytest.raises(ValueError, match="reach must be a number in"):
        s.sample(np.random.default_rng(0), reach=bad)  # type: ignore[arg-type]
    env = gym.make("RadialIBVS/Parking-v0", scenario="random", physics="kinematic")
    with pytest.raises(ValueError, match="start_reach must be a number in"):
        env.unwrapped.start_reach = bad  # type: ignore[attr-defined]
    assert env.unwrapped.start_reach == 1.0  # type: ignore[attr-defined]


def test_reach_needs_starts_drawn_anywhere() -> None:
    with pytest.raises(ValueError, match="reach < 1 needs a start 'anywhere'"):
        load_scenario("paper-sim").sample(np.random.default_rng(0), reach=0.5)
    with pytest.raises(ValueError, match="fixes the start of task"):
        gym.make("RadialIBVS/Parking-v0", scenario="paper-sim", start_reach=0.5)


def test_start_reach_applies_to_the_scalar_and_the_vector_env_alike() -> None:
    kwargs = {"scenario": "random", "physics": "kinematic", "obs_mode": "features"}
    env = gym.make("RadialIBVS/Parking-v0", start_reach=0.1, **kwargs)
    _, info = env.reset(seed=3)
    assert info["position_error_m"] <= 0.6 + 1e-9
    venv = make_vec_env("RadialIBVS/Parking-v0", 4, seed=3, **kwargs)
    venv.reset()
    venv.set_attr("start_reach", 0.1)
    assert venv.get_attr("start_reach") == [0.1] * 4
    obs, infos = venv.env.reset(seed=3)
    np.testing.assert_array_less(infos["position_error_m"], 0.6 + 1e-9)
    first = {k: v[0] for k, v in obs.items()}
    scalar, _ = env.reset(seed=3)
    for key, value in scalar.items():
        np.testing.assert_allclose(first[key], value, atol=1e-6, err_msg=key)
    with pytest.raises(AttributeError, match="shared by all envs"):
        venv.set_attr("start_reach", 0.5, indices=[0])
    with pytest.raises(AttributeError, match="cannot set 'physics'"):
        venv.set_attr("physics", "pymunk")
    with pytest.raises(ValueError, match="start_reach must be"):
        venv.set_attr("start_reach", 2.0)


def test_schedule_is_linear_then_full() -> None:
    c = CurriculumConfig(start=0.2, until=0.5)
    assert c.reach(0.0) == pytest.approx(0.2)
    assert c.reach(0.25) == pytest.approx(0.6)
    assert c.reach(0.5) == c.reach(0.9) == 1.0


@pytest.mark.parametrize(
    ("data", "match"),
    [
        ({"start": 0}, "start must be a number in"),
        ({"until": 2}, "until must be a number in"),
        ({"start": "x"}, "start must be a number in"),
        ({"begin": 0.1}, "unknown key"),
        ([0.1], "must be a mapping"),
    ],
)
def test_bad_curriculum_configs_are_named(data: object, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        CurriculumConfig.from_mapping(data, "curriculum")  # type: ignore[arg-type]
