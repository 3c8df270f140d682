"""How far the pose layer's solved goal is from the true one, through the `imperfect` cameras.

Usage::

    python research/diagnostics/pose_layer_errors.py [--episodes 40] [--seed 100000]

:func:`radial_ibvs_agents.learned.networks.pose_layer.solve_goal_pose` solves the goal's planar pose
from the bearings of one image against the goal image. For held-out rooms (the ``imperfect`` suite's
seeds and cameras) this script prints

- through the calibration error (principal point (2, -1) px, focal ratio +1 %): how far the
  solved position is from the goal, and the solved heading from the true one, with the robot
  on the goal position turned 0-180 deg from the goal heading (the error cancels only at the
  goal heading);
- through 1 px of noise: the solved position's error along the planner's own paths, by
  distance to the goal (one frame, no filtering).

It calls the env's own camera model at chosen poses (``env.unwrapped.image`` on the episode's
set-up): a diagnostic, not something a policy could do.
"""

from __future__ import annotations

import argparse

import gymnasium as gym
import numpy as np
import torch
from _common import solve_one  # research/diagnostics/_common.py

import radial_ibvs_gym  # noqa: F401  (registers the envs)
from radial_ibvs_agents.analytic import make_analytic
from radial_ibvs_agents.experiments.suites import HELD_OUT_SEED
from radial_ibvs_agents.learned.dagger.distill import goal_in_robot_frame

ENV = {"scenario": "random", "physics": "kinematic", "obs_mode": "features", "goal_depths": True}
CAMERA = {"mirror": "A", "non_central_offset": 0.01}
CALIBRATION = {"principal_point_offset": [2.0, -1.0], "focal_ratio_error": 0.01}


def turned_at_goal(episodes: int, seed: int, angles: tuple[float, ...]) -> dict[float, list]:
    """``[(position off (m), heading off (rad)), ...]`` per angle: the solved pose's errors, the
    robot on the goal turned by ``angles`` (degrees)."""
    env = gym.make("RadialIBVS/Parking-v0", **ENV, camera={**CAMERA, "imperfections": CALIBRATION})
    out: dict[float, list] = {a: [] for a in angles}
    for episode in range(episodes):
        env.reset(seed=seed + episode)
        u = env.unwrapped
        setup = u._setup
        for angle in angles:
            pose = np.array(setup.episode.goal, dtype=float)  # a copy: the goal stays
            pose[2] += np.radians(angle)
            points, visible = u.image(setup, pose, "current", u.np_random)
            solved, valid = solve_one(
                points, visible, setup.goal_points, setup.goal_visible, setup.goal_depths
            )
            # the goal's heading relative to the robot's is -angle
            heading = np.arctan2(solved[3], solved[2]) + np.radians(angle)
            heading = (heading + np.pi) % (2 * np.pi) - np.pi
            off = (np.hypot(solved[0], solved[1]), abs(heading)) if valid else (np.inf, np.inf)
            out[angle].append(off)
    env.close()
    return out


def along_planner_paths(episodes: int, seed: int) -> np.ndarray:
    """``(K, 2)``: distance to the goal and the solved position's error (m) along the paths."""
    env = gym.make(
        "RadialIBVS/Parking-v0", **ENV, privileged=True, privileged_map=True,
        camera={**CAMERA, "imperfections": {"pixel_noise_std": 1.0}},
    )  # fmt: skip
    planner = make_analytic("planner")
    rows = []
    for episode in range(episodes):
        obs, _ = env.reset(seed=seed + episode)
        state = None
        for _ in range(600):
            solved, valid = solve_one(
                obs["points"].reshape(-1, 2), obs["visible"] > 0.5,
                obs["goal_points"].reshape(-1, 2),
                np.linalg.norm(obs["goal_points"].reshape(-1, 2), axis=1),
                obs["goal_depths"],
            )  # fmt: skip
            truth = 3.0 * goal_in_robot_frame(obs)[0, :2].astype(float)
            if valid:
                rows.append([np.hypot(*truth), np.hypot(*(solved[:2] - truth))])
            action, state = planner.predict(obs, state)
            obs, _, terminated, truncated, _ = env.step(action)
            if terminated or truncated:
                break
    env.close()
    return np.asarray(rows)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--episodes", type=int, default=40)
    parser.add_argument("--seed", type=int, default=HELD_OUT_SEED)
    args = parser.parse_args()
    torch.set_num_threads(1)
    print(f"pp (2, -1) px, fy +1 %; the robot on the goal, {args.episodes} held-out rooms")
    print(
        "| turned from the goal heading | solved position off: median | 90th percentile "
        "| solved heading off: median | 90th percentile |"
    )
    print("|---|---|---|---|---|")
    angles = (0, 2, 10, 30, 45, 90, 180)
    for angle, rows in turned_at_goal(args.episodes, args.seed, angles).items():
        off, heading = np.asarray(rows).T
        print(
            f"| {angle:g} deg | {np.median(off) * 100:.1f} cm "
            f"| {np.percentile(off, 90) * 100:.1f} cm "
            f"| {np.degrees(np.median(heading)):.2f} deg "
            f"| {np.degrees(np.percentile(heading, 90)):.2f} deg |"
        )
    rows = along_planner_paths(max(1, args.episodes // 7), args.seed)
    print(f"\n1 px of noise, along the planner's paths ({max(1, args.episodes // 7)} rooms)")
    print("| distance to the goal | steps | solved position off: median | 90th percentile |")
    print("|---|---|---|---|")
    for low, high in ((0.0, 0.05), (0.05, 0.3), (0.3, 1.0), (1.0, 10.0)):
        sel = rows[(rows[:, 0] >= low) & (rows[:, 0] < high), 1]
        if len(sel):
            print(
                f"| {low:g}-{high:g} m | {len(sel)} | {np.median(sel) * 100:.2f} cm "
                f"| {np.percentile(sel, 90) * 100:.2f} cm |"
            )


if __name__ == "__main__":
    main()
