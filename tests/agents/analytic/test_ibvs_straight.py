"""``ibvs-straight``: the turn-first IBVS from the image alone."""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import radial_ibvs_gym  # noqa: F401
from radial_ibvs_agents import make_policy
from radial_ibvs_agents.analytic.ibvs_straight import StraightIBVSPolicy, straight_command

LIMITS = dict(lam=0.5, v_max=1.2, omega_max=5.2, stop_radius=0.002, stop_heading=0.002)
LAW = dict(**LIMITS, rotate_radius=0.02, align_tolerance=math.radians(5), turn_gain=2.0)


def _command(v: list[float], gamma: float = 0.0) -> tuple[float, float]:
    v_l, omega = straight_command(np.array(v), gamma, **LAW)
    return float(v_l), float(omega)


def test_it_turns_in_place_until_the_goal_lies_along_its_axis() -> None:
    v_l, omega = _command([0.0, 0.5])  # the goal to the left, 90 degrees: turn, do not drive
    assert v_l == 0.0 and omega > 0.0
    v_l, omega = _command([0.3, -0.3])  # 45 degrees to the right
    assert v_l == 0.0 and omega < 0.0


def test_it_drives_forwards_or_backwards_whichever_needs_less_turning() -> None:
    v_l, omega = _command([0.5, 0.01])
    assert v_l > 0.0 and omega > 0.0 and abs(omega) < 0.1  # aligned: drive, keep aligned
    v_l, omega = _command([-0.5, 0.01])  # behind: backwards, no half turn
    assert v_l < 0.0 and abs(omega) < 0.1
    v_l, omega = _command([-0.3, 0.4])  # behind and to the left: turn right to back up
    assert v_l == 0.0 and omega < 0.0


def test_the_final_rotation_and_the_stop_rule() -> None:
    v_l, omega = _command([0.004, 0.004], gamma=0.5)  # within rotate_radius: turn to heading
    assert v_l == pytest.approx(0.004) and omega == pytest.approx(0.25)
    assert _command([0.0005, 0.0], gamma=0.001) == (0.0, 0.0)


@given(
    vx=st.floats(-3, 3),
    vy=st.floats(-3, 3),
    gamma=st.floats(-math.pi, math.pi),
)
def test_the_command_respects_the_limits_and_never_drives_misaligned(
    vx: float, vy: float, gamma: float
) -> None:
    v_l, omega = _command([vx, vy], gamma)
    assert abs(v_l) <= LAW["v_max"] + 1e-12 and abs(omega) <= LAW["omega_max"] + 1e-12
    delta = math.atan2(vy, vx)
    misaligned = min(abs(delta), math.pi - abs(delta)) > LAW["align_tolerance"] + 1e-9
    if math.hypot(vx, vy) / LAW["lam"] >= LAW["rotate_radius"] and misaligned:
        assert v_l == 0.0


def test_a_batch_is_the_rows_one_by_one() -> None:
    policy = make_policy("ibvs-straight")
    env = gym.make("RadialIBVS/Parking-v0", scenario="random", physics="kinematic",
                   **policy.env_kwargs)  # fmt: skip
    observations = []
    for seed in range(6):
        obs, _ = env.reset(seed=seed)
        for _ in range(seed * 7):
            obs = env.step(policy.predict(obs)[0])[0]
        observations.append(obs)
    batch = {k: np.stack([o[k] for o in observations]) for k in observations[0]}
    rows = np.stack([policy.predict(o)[0] for o in observations])
    np.testing.assert_allclose(policy.predict(batch)[0], rows, atol=2e-5)


def test_it_needs_the_image_only_and_parks_the_papers_tasks() -> None:
    policy = make_policy("ibvs-straight")
    assert isinstance(policy, StraightIBVSPolicy) and policy.env_kwargs == {"goal_depths": True}
    env = gym.make("RadialIBVS/Parking-v0", physics="kinematic", **policy.env_kwargs)
    for task in range(4):
        obs, info = env.reset(seed=0, options={"task": task})
        for _ in range(600):
            obs, _, terminated, truncated, info = env.step(policy.predict(obs)[0])
            if terminated or truncated:
                break
        assert info["is_success"], (task, info["position_error_m"], info["heading_error_deg"])


def test_bad_settings_are_named() -> None:
    with pytest.raises(ValueError, match="align_tolerance"):
        StraightIBVSPolicy(align_tolerance=0.0)
    with pytest.raises(ValueError, match="variant='paper'"):
        StraightIBVSPolicy(variant="mean")
