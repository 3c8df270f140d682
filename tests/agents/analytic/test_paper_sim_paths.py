"""paper-sim's choices (start (3, 3) m, camera 1.8 m, mirror A) keep all 8 eq. (39) points in
view along the paths of the smooth control law driven by the exact poses (the pose oracle)."""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import pytest

import radial_ibvs_gym  # noqa: F401
from radial_ibvs_agents.analytic.smooth_control import SmoothControlLaw, ego_polar


@pytest.mark.parametrize("physics", ["kinematic", "pymunk"])
@pytest.mark.parametrize("task", range(4))
def test_all_eq39_points_stay_visible_on_the_oracle_paths(task: int, physics: str) -> None:
    env = gym.make("RadialIBVS/Parking-v0", task=task, physics=physics)
    law = SmoothControlLaw(slowdown_radius=0.5)
    robot = env.unwrapped.robot
    _, info = env.reset(seed=0)
    visible = [info["n_visible"]]
    for _ in range(600):
        r, phi, delta = ego_polar(info["goal_pose"], info["robot_pose"])
        v, omega = law.velocity(float(r), float(phi), float(delta))
        action = np.array([v / robot.max_linear_speed, omega / robot.max_angular_speed])
        _, _, terminated, truncated, info = env.step(action.astype(np.float32))
        visible.append(info["n_visible"])
        if terminated or truncated:
            break
    assert min(visible) == 8
    assert info["position_error_m"] < 0.05 and not info["collision"]
    assert math.isfinite(info["heading_error_deg"])
