"""The paper's IBVS on the four paper-sim tasks (a preview of ``radial-ibvs reproduce``).

Usage: ``python benchmarks/ibvs_paper_sim.py``. Kinematic backend, control period 0.05 s,
lambda = 0.5, k1 = 4, k2 = 12, exact depths and depths x1.3. The episode ends at the env's
success test (2 cm, 2 deg).
"""

from __future__ import annotations

import gymnasium as gym
import numpy as np

import radial_ibvs_gym  # noqa: F401
from agents.ibvs_core import GoalModel, ibvs_twist, robot_command


def run(task: int, depth_scale: float, lam: float = 0.5) -> tuple[dict, float, float]:
    """One episode; returns the last info, the time to park (s) and the path length (m)."""
    env = gym.make(
        "RadialIBVS/Parking-v0",
        task=task,
        physics="kinematic",
        control_dt=0.05,
        max_episode_steps=4000,
        depth_scale=depth_scale,
    )
    obs, info = env.reset(seed=0)
    model = GoalModel.from_goal(
        obs["goal_points"].reshape(-1, 2).astype(float), info["goal_depths"]
    )
    robot = env.unwrapped.robot
    path, prev, t = 0.0, info["robot_pose"][:2], 0.0
    while True:
        x_n = obs["points"].reshape(-1, 2).astype(np.float64)
        x_n /= np.linalg.norm(x_n, axis=1, keepdims=True)
        v, _, gamma = ibvs_twist(x_n, model, lam=lam)
        v_l, omega = robot_command(
            v, gamma, lam, v_max=robot.max_linear_speed, omega_max=robot.max_angular_speed
        )
        action = np.array([v_l / robot.max_linear_speed, omega / robot.max_angular_speed])
        obs, _, terminated, truncated, info = env.step(action.astype(np.float32))
        t += 0.05
        path += float(np.hypot(*(info["robot_pose"][:2] - prev)))
        prev = info["robot_pose"][:2]
        if terminated or truncated:
            return info, t, path


def main() -> None:
    """Print the table."""
    print("goal yaw  d* scale  success  time [s]  path [m]  pos err [cm]  head err [deg]")
    for task, yaw in enumerate((0, 90, 180, 270)):
        for scale in (1.0, 1.3):
            info, t, path = run(task, scale)
            print(
                f"{yaw:>8}  {scale:>8.1f}  {info['is_success']!s:>7}  {t:>8.2f}  {path:>8.2f}"
                f"  {100 * info['position_error_m']:>12.2f}  {info['heading_error_deg']:>14.3f}"
            )


if __name__ == "__main__":
    main()
