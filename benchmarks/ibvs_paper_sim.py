"""The paper's IBVS on the four paper-sim tasks (a preview of ``radial-ibvs reproduce``).

Usage: ``python benchmarks/ibvs_paper_sim.py``. Kinematic backend, control period 0.05 s,
lambda = 0.5, k1 = 4, k2 = 12, exact depths and depths x1.3. The episode ends at the env's
success test (2 cm, 2 deg).
"""

from __future__ import annotations

import gymnasium as gym

import radial_ibvs_gym  # noqa: F401
from agents.ibvs_core import drive
from radial_ibvs_gym.physics import RobotConfig


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
    info, steps, path = drive(env, RobotConfig(), lam=lam)
    return info, 0.05 * steps, path


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
