"""The vector env through an imperfect camera: batched projection against env by env.

Usage: ``python benchmarks/bench_camera.py [--envs 64 256] [--steps 100] [--repeats 2]``.

With camera imperfections (drawn per episode here, as in domain-randomised training:
``research/configs/ppo_residual_dr.yaml``) every robot's landmarks are projected exactly through
the non-central mirror. :func:`radial_ibvs_gym.camera.measurement.camera_images` finds the
reflection points of all the robots in one call (a first guess from a table of the mirror's
roots, a bracket about it, Illinois iterations: :mod:`radial_ibvs_gym.camera.meridian`); the
"env by env" row replaces it with one :func:`~radial_ibvs_gym.camera.measurement.camera_image`
call per robot. Both runs are seeded alike and send the same random actions, so they step the
same trajectories (the batched path is bit-for-bit the same). The ideal camera (eq. 9 in closed
form) is the ceiling; "ideal / batched" is how many times slower the real camera steps (the
goal: at most 3). Env steps per second (robots times batched steps), best of ``--repeats``.
"""

from __future__ import annotations

import argparse
import platform
import time
from typing import Any

import gymnasium as gym
import numpy as np

import radial_ibvs_gym  # noqa: F401  (registers the environments)
from radial_ibvs_gym.camera import measurement as logic

KWARGS: dict[str, Any] = {
    "scenario": "random",
    "physics": "kinematic",
    "obs_mode": "features",
    "goal_depths": True,
    "max_landmarks": 16,
}
CAMERA = {
    "mirror": "A",
    "non_central_offset": 0.01,
    "imperfection_ranges": {
        "principal_point_offset": 4.0,
        "focal_ratio_error": 0.03,
        "pixel_noise_std": [0.0, 1.5],
    },
}


def _one_by_one(cameras: Any, p_cam: Any, rngs: Any) -> Any:
    rows = [logic.camera_image(c, p, r) for c, p, r in zip(cameras, p_cam, rngs, strict=True)]
    return np.stack([r[0] for r in rows]), np.stack([r[1] for r in rows])


def rate(n: int, steps: int, repeats: int, **extra: Any) -> float:
    """Best env steps per second of ``steps`` random actions on ``n`` robots."""
    best = float("inf")
    for _ in range(repeats):
        envs = gym.make_vec("RadialIBVS/Parking-v0", num_envs=n, **KWARGS, **extra)
        envs.reset(seed=0)
        actions = np.random.default_rng(0).uniform(-1, 1, (steps, n, 2))
        start = time.perf_counter()
        for a in actions:
            envs.step(a)
        best = min(best, time.perf_counter() - start)
        envs.close()
    return n * steps / best


def main() -> None:
    """Print the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--envs", type=int, nargs="+", default=[64, 256])
    parser.add_argument("--steps", type=int, default=100)
    parser.add_argument("--repeats", type=int, default=2)
    args = parser.parse_args()
    print(f"# imperfect camera, drawn per episode; {platform.processor() or platform.machine()}")
    print("| envs | ideal camera | imperfect, batched | imperfect, env by env | ideal / batched |")
    print("|---:|---:|---:|---:|---:|")
    batched_fn = logic.camera_images
    for n in args.envs:
        ideal = rate(n, args.steps, args.repeats)
        batched = rate(n, args.steps, args.repeats, camera=CAMERA)
        logic.camera_images = _one_by_one  # type: ignore[assignment]
        try:
            single = rate(n, args.steps, args.repeats, camera=CAMERA)
        finally:
            logic.camera_images = batched_fn  # type: ignore[assignment]
        print(f"| {n} | {ideal:,.0f} | {batched:,.0f} | {single:,.0f} | {ideal / batched:.1f}x |")


if __name__ == "__main__":
    main()
