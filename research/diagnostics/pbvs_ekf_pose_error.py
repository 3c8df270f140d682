"""How far the filtered pose of ``pbvs-ekf`` lies from the truth, beside the image's solve.

Usage::

    python research/diagnostics/pbvs_ekf_pose_error.py [--episodes 20] [--noise 1.0]

Drives ``pbvs-ekf`` in held-out random rooms (seeds from 100,000, kinematic) through a camera with
``--noise`` pixels of noise and, at every frame, compares with the true goal pose in the robot's
frame (the privileged observation, read only here): the pose the image alone gives
(:func:`radial_ibvs_agents.analytic.pbvs.solve_goal_pose`) and the filter's after its update with
that frame. Prints the median position errors (centimetres) and the number of frames.
"""

from __future__ import annotations

import argparse

import gymnasium as gym
import numpy as np

import radial_ibvs_gym  # noqa: F401  (registers the envs)
from radial_ibvs_agents import make_policy
from radial_ibvs_gym.geometry import pose_in_frame


def measure(episodes: int, noise: float) -> tuple[float, float, int]:
    """Median position error of the solve and of the filter, metres, and the frames compared."""
    policy = make_policy("pbvs-ekf")
    camera = {"mirror": "A", "non_central_offset": 0.01}
    camera["imperfections"] = {"pixel_noise_std": noise}  # type: ignore[assignment]
    env = gym.make(
        "RadialIBVS/Parking-v0", scenario="random", physics="kinematic", goal_depths=True,
        privileged=True, camera=camera,
    )  # fmt: skip
    solve_errors, filter_errors = [], []
    for seed in range(100_000, 100_000 + episodes):
        obs, _ = env.reset(seed=seed)
        state, start = None, np.array([True])
        for _ in range(600):
            action, state = policy.predict(obs, state, start)
            start = np.array([False])
            obs, _, terminated, truncated, _ = env.step(action)
            truth = np.array(pose_in_frame(obs["robot_pose"], obs["goal_pose"]))
            batch = {k: v[None] for k, v in obs.items()}
            solved, valid = policy.goal_pose(batch)
            if valid[0] and state.started[0]:
                # what the next call does with this frame
                mean, _ = policy._update(state.mean, state.cov, batch, state.started)
                solve_errors.append(np.hypot(*(solved[0, :2] - truth[:2])))
                filter_errors.append(np.hypot(*(mean[0, :2] - truth[:2])))
            if terminated or truncated:
                break
    return float(np.median(solve_errors)), float(np.median(filter_errors)), len(solve_errors)


def main() -> None:
    """Print the comparison."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--episodes", type=int, default=20, help="default: %(default)s")
    parser.add_argument("--noise", type=float, default=1.0, help="pixels (default: %(default)s)")
    args = parser.parse_args()
    solve, filtered, frames = measure(args.episodes, args.noise)
    print(
        f"median position error of the goal's pose, {args.noise} px noise, {args.episodes} "
        f"held-out rooms: image solve {100 * solve:.2f} cm, filter {100 * filtered:.2f} cm "
        f"({frames} frames)"
    )


if __name__ == "__main__":
    main()
