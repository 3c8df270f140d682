"""Camera imperfections drawn per episode from the env's generator, reported in info and rows."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import radial_ibvs_gym  # noqa: F401
from radial_ibvs_gym.camera import ImperfectionRanges, Imperfections
from radial_ibvs_gym.config import ConfigError

MIRROR = {"mirror": "A", "non_central_offset": 0.01}
RANGES = {"principal_point_offset": 3.0, "focal_ratio_error": 0.02, "pixel_noise_std": [0.5, 1.0]}
KW = dict(scenario="random", physics="kinematic", goal_depths=True)


@given(
    r=st.floats(0, 10),
    e=st.floats(0, 0.5),
    lo=st.floats(0, 2),
    span=st.floats(0, 2),
    t=st.floats(0, 0.5),
    seed=st.integers(0, 2**32 - 1),
)
def test_a_draw_lies_in_its_ranges_around_the_fixed_imperfections(
    r: float, e: float, lo: float, span: float, t: float, seed: int
) -> None:
    base = Imperfections(principal_point_offset=(1.0, -2.0), focal_ratio_error=0.01)
    ranges = ImperfectionRanges(
        principal_point_offset=r, focal_ratio_error=e, pixel_noise_std=(lo, lo + span), tilt=t
    )
    drawn = ranges.draw(np.random.default_rng(seed), base)
    du, dv = drawn.principal_point_offset
    assert abs(du - 1.0) <= r and abs(dv + 2.0) <= r
    assert abs(drawn.focal_ratio_error - 0.01) <= e
    assert lo <= drawn.pixel_noise_std <= lo + span
    assert all(abs(v) <= t for v in drawn.tilt)
    assert drawn == ranges.draw(np.random.default_rng(seed), base)  # the same seed, the same draw


def test_each_reset_draws_a_camera_reported_in_info_and_rows() -> None:
    from radial_ibvs_agents import make_policy
    from radial_ibvs_agents.rollouts import make_env, run_episode
    from radial_ibvs_agents.rows import episode_row

    camera = {**MIRROR, "imperfection_ranges": RANGES}
    env = gym.make("RadialIBVS/Parking-v0", camera=camera, **KW)
    draws = [env.reset(seed=s)[1]["camera_imperfections"] for s in range(5)]
    assert len({d["principal_point_du"] for d in draws}) == 5
    assert all(0.5 <= d["pixel_noise_std"] <= 1.0 for d in draws)
    assert env.reset(seed=3)[1]["camera_imperfections"] == draws[3]
    policy = make_policy("ibvs-backward")
    env = make_env(policy, "random", {"physics": "kinematic", "camera": camera})
    log = run_episode(policy, env, seed=3)
    assert episode_row(log)["camera_imperfections"] == draws[3]


def test_without_ranges_the_episodes_are_unchanged() -> None:
    plain = gym.make("RadialIBVS/Parking-v0", camera=MIRROR, **KW)
    explicit = gym.make("RadialIBVS/Parking-v0", camera={**MIRROR, "imperfection_ranges": None},
                        **KW)  # fmt: skip
    a, info = plain.reset(seed=7)
    b, _ = explicit.reset(seed=7)
    assert "camera_imperfections" not in info
    assert all(np.array_equal(a[k], b[k]) for k in a)


def test_the_native_vector_env_draws_as_the_scalar_envs_do() -> None:
    camera = {**MIRROR, "imperfection_ranges": RANGES}
    args = dict(num_envs=3, camera=camera, **KW)
    native = gym.make_vec("RadialIBVS/Parking-v0", vectorization_mode="vector_entry_point", **args)
    sync = gym.make_vec("RadialIBVS/Parking-v0", vectorization_mode="sync", **args)
    a, ia = native.reset(seed=5)
    b, ib = sync.reset(seed=5)
    rng = np.random.default_rng(0)
    for _ in range(60):
        assert all(np.array_equal(a[k], b[k]) for k in a)
        for key, value in ib["camera_imperfections"].items():
            np.testing.assert_array_equal(ia["camera_imperfections"][key], value)
        actions = rng.uniform(-1, 1, (3, 2)).astype(np.float32)
        a, ra, *_, ia = native.step(actions)
        b, rb, *_, ib = sync.step(actions)
        np.testing.assert_array_equal(ra, rb)


def test_bad_ranges_are_named() -> None:
    with pytest.raises(ConfigError, match="focal_ratio_error"):
        gym.make("RadialIBVS/Parking-v0", camera={**MIRROR, "imperfection_ranges":
                 {"focal_ratio_error": 1.5}}, **KW)  # fmt: skip
    with pytest.raises(ConfigError, match="pixel_noise_std"):
        gym.make("RadialIBVS/Parking-v0", camera={**MIRROR, "imperfection_ranges":
                 {"pixel_noise_std": [2.0, 1.0]}}, **KW)  # fmt: skip
    with pytest.raises(ValueError, match="measurement='detected' does not take"):
        gym.make("RadialIBVS/Parking-v0", scenario="paper-lab", measurement="detected",
                 camera={**MIRROR, "imperfection_ranges": RANGES})  # fmt: skip
