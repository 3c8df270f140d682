"""How far a noisy goal image puts the goal: a limit for every image-based policy.

Usage::

    python benchmarks/goal_image_limit.py [--episodes 100] [--seed 100000]

An image-based policy is told the goal by one image taken there. Through a camera with pixel
noise that image holds one draw of the noise, fixed for the episode: no filtering of the
current images removes it. For each held-out room (the ``imperfect`` suite's seeds and
cameras) this script takes the noise-free image at the goal through the same (miscalibrated)
camera, solves the goal's pose from it against the episode's noisy goal image
(:func:`agents.learned.pose_layer.solve_goal_pose`, least squares over the bearings) and
prints how far that pose lies from the true goal: where a policy that matched the goal image
perfectly would stop. The share within the success tolerance (2 cm / 2 deg) estimates the
most an image-based policy parks through that camera (the least-squares pose is close to,
not exactly, the best estimate from the goal image).

It reads the episode's set-up (``env.unwrapped._setup``) for the noisy goal image and calls
the env's own camera model at the goal: a diagnostic, not something a policy could do.
"""

from __future__ import annotations

import argparse

import gymnasium as gym
import numpy as np
import torch

import radial_ibvs_gym  # noqa: F401  (registers the envs)
from agents.experiments.suites import HELD_OUT_SEED
from agents.learned.pose_layer import solve_goal_pose

ENV = {"scenario": "random", "physics": "kinematic", "obs_mode": "features", "goal_depths": True}
CAMERA = {"mirror": "A", "non_central_offset": 0.01}
CALIBRATION = {"principal_point_offset": [2.0, -1.0], "focal_ratio_error": 0.01}
VARIANTS = {  # label: (the noisy camera's imperfections, the same camera without the noise)
    "noise 0.5 px": ({"pixel_noise_std": 0.5}, {}),
    "noise 1 px": ({"pixel_noise_std": 1.0}, {}),
    "pp (2, -1) px, fy +1 %": (CALIBRATION, CALIBRATION),
    "all together": ({**CALIBRATION, "pixel_noise_std": 1.0}, CALIBRATION),
}


def goal_offsets(noisy: dict, clean: dict, episodes: int, seed: int) -> np.ndarray:
    """Return ``(episodes, 2)``: each room's image goal's distance (m) and heading (deg) off."""
    envs = [
        gym.make("RadialIBVS/Parking-v0", **ENV, camera={**CAMERA, "imperfections": imp})
        for imp in (noisy, clean)
    ]
    out = []
    for episode in range(episodes):
        obs, _ = envs[0].reset(seed=seed + episode)
        envs[1].reset(seed=seed + episode)
        setup, clean_env = envs[0].unwrapped._setup, envs[1].unwrapped
        goal = np.asarray(setup.episode.goal, dtype=float)
        now, visible = clean_env.image(clean_env._setup, goal, "current", clean_env.np_random)
        n = len(now)
        mask = (visible & np.asarray(setup.goal_visible)).astype(float)
        pose, valid = solve_goal_pose(
            torch.tensor(now)[None],
            torch.tensor(np.asarray(setup.goal_points))[None],
            torch.tensor(np.asarray(obs["goal_depths"], dtype=float)[:n])[None],
            torch.tensor(mask)[None],
        )
        p = pose[0].numpy()
        heading = np.degrees(abs(np.arctan2(p[3], p[2]))) if bool(valid[0]) else np.inf
        out.append([np.hypot(p[0], p[1]) if bool(valid[0]) else np.inf, heading])
    for env in envs:
        env.close()
    return np.asarray(out)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--episodes", type=int, default=100)
    parser.add_argument("--seed", type=int, default=HELD_OUT_SEED)
    args = parser.parse_args()
    torch.set_num_threads(1)
    print(f"held-out rooms {args.seed}-{args.seed + args.episodes - 1}, camera mirror A")
    print("| camera | image goal off: median / 90th pct | within 2 cm / 2 deg | 10 cm / 5 deg |")
    print("|---|---|---|---|")
    for label, (noisy, clean) in VARIANTS.items():
        off = goal_offsets(noisy, clean, args.episodes, args.seed)
        within = np.mean((off[:, 0] < 0.02) & (off[:, 1] < 2.0))
        near = np.mean((off[:, 0] < 0.10) & (off[:, 1] < 5.0))
        print(
            f"| {label} | {np.median(off[:, 0]) * 100:.2f} / "
            f"{np.percentile(off[:, 0], 90) * 100:.2f} cm, {np.median(off[:, 1]):.2f} deg "
            f"| {within:.0%} | {near:.0%} |"
        )


if __name__ == "__main__":
    main()
