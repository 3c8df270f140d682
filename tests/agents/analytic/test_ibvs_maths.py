"""The paper's IBVS maths (eq. 30, 36-37): the rotation estimate and the velocity direction."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from radial_ibvs_agents.analytic.ibvs_maths import GoalModel, ibvs_twist
from radial_ibvs_gym import paper
from radial_ibvs_gym.camera import radial_points
from radial_ibvs_gym.geometry import world_to_camera

GOAL_POSE = np.array(paper.goal_pose(0))
P_WORLD = paper.EQ39_POINTS


def goal_model(depth_scale: float = 1.0) -> GoalModel:
    goal = radial_points(world_to_camera(P_WORLD, GOAL_POSE, paper.CAMERA_HEIGHT_M))
    return GoalModel.from_goal(goal.x_n, depth_scale * goal.d)


def current_points(t_goal: np.ndarray, theta: float) -> np.ndarray:
    """Image of the scene from the goal pose moved by t (goal frame) and turned by theta."""
    c, s = math.cos(GOAL_POSE[2]), math.sin(GOAL_POSE[2])
    pose = GOAL_POSE + np.array(
        [c * t_goal[0] - s * t_goal[1], s * t_goal[0] + c * t_goal[1], theta]
    )
    return radial_points(world_to_camera(P_WORLD, pose, paper.CAMERA_HEIGHT_M)).x_n


@settings(max_examples=100, deadline=None)
@given(direction=st.floats(-math.pi, math.pi), theta=st.floats(-3.0, 3.0))
def test_gamma_is_accurate_near_the_goal_only_with_the_derived_sign(direction, theta) -> None:
    """r = 1 cm from the goal: gamma = -theta to 1e-5 rad (derived sign), not printed sign."""
    model = goal_model()
    t = 0.01 * np.array([math.cos(direction), math.sin(direction)])
    x_n = current_points(t, theta)
    _, _, gamma = ibvs_twist(x_n, model, lam=0.5)
    assert abs(math.remainder(gamma + theta, 2 * math.pi)) < 1e-5


def test_the_printed_sign_of_eq30_misestimates_gamma() -> None:
    model = goal_model()
    worst = 0.0
    for direction in np.linspace(-math.pi, math.pi, 16, endpoint=False):
        t = 0.01 * np.array([math.cos(direction), math.sin(direction)])
        _, _, gamma = ibvs_twist(current_points(t, 0.4), model, compensation="printed")
        worst = max(worst, abs(math.remainder(gamma + 0.4, 2 * math.pi)))
    assert worst > 1e-4  # errors of order r / d: the misprint is real


@pytest.mark.parametrize("theta", [0.0, 1.0, -2.5])
def test_velocity_points_back_to_the_goal_in_the_current_frame(theta: float) -> None:
    model = goal_model()
    t = np.array([0.006, -0.008])  # 1 cm
    v, omega_z, _ = ibvs_twist(current_points(t, theta), model, lam=2.0)
    expected = -2.0 * (
        np.array([[math.cos(theta), math.sin(theta)], [-math.sin(theta), math.cos(theta)]]) @ t
    )
    np.testing.assert_allclose(v, expected, atol=2e-4)  # first order in r
    assert omega_z == pytest.approx(-2.0 * theta, abs=1e-4)


def test_scaled_depths_scale_the_translation() -> None:
    """With d* scaled by 1.3 (the paper's second simulation) v* grows by 1.3: faster, same path."""
    t = np.array([0.006, -0.008])
    v1, _, _ = ibvs_twist(current_points(t, 0.2), goal_model(1.0))
    v13, _, _ = ibvs_twist(current_points(t, 0.2), goal_model(1.3))
    np.testing.assert_allclose(v13, 1.3 * v1, rtol=1e-9)
