"""The vector env through an imperfect camera: batched projection against env by env.

Usage: ``python benchmarks/bench_camera.py [--envs 64 256] [--steps 100] [--rounds 3]
[--env-by-env]``.

With camera imperfections (drawn per episode here, as in domain-randomised training:
``research/configs/ppo_residual_dr.yaml``) every robot's landmarks are projected exactly through
the non-central mirror. The env keeps its cameras as arrays
(:class:`radial_ibvs_gym.envs.camera_rows.CameraRows`), finds the reflection points of all the
robots in one call (a first guess from a table of the mirror's roots, a bracket about it,
Illinois iterations: :mod:`radial_ibvs_gym.camera.meridian`) and draws each robot's noise from
its own generator a block of steps at a time (:mod:`radial_ibvs_gym.envs.noise_blocks`). The
``--env-by-env`` column replaces that with one
:func:`~radial_ibvs_gym.camera.measurement.camera_image` call per robot; every run is seeded
alike and sends the same random actions, so they step the same trajectories (the batched path
is bit-for-bit the same). The ideal camera (eq. 9 in closed form) is the ceiling; "ideal /
imperfect" is how many times slower the real camera steps (the goal: at most 3), the median of
``--rounds`` rounds, each timing the ideal and the imperfect env one after the other. Env steps
per second (robots times batched steps).
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
from radial_ibvs_gym.envs.camera_rows import CameraRows

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


def _one_by_one(self: Any, indices: Any, p_cam: Any, rngs: Any) -> Any:
    """``CameraRows.measure`` camera by camera: one ``camera_image`` call per robot."""
    rows = []
    for i, p in zip(indices.tolist(), p_cam, strict=True):
        self.noise.sync(i, rngs[i])  # its generator as one draw a step leaves it
        rows.append(logic.camera_image(self.cameras[i], p, rngs[i]))
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
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument(
        "--env-by-env", action="store_true", help="also time one camera_image call per robot"
    )
    args = parser.parse_args()
    for name in ("steps", "rounds"):
        if getattr(args, name) < 1:
            parser.error(f"--{name} must be a positive integer, got {getattr(args, name)}")
    print(f"# imperfect camera, drawn per episode; {platform.processor() or platform.machine()}")
    print("| envs | ideal camera | imperfect | ideal / imperfect (median, each round) |")
    print("|---:|---:|---:|---|")
    for n in args.envs:
        ideal, real = [], []
        for _ in range(args.rounds):
            ideal.append(rate(n, args.steps, 1))
            real.append(rate(n, args.steps, 1, camera=CAMERA))
        ratios = [a / b for a, b in zip(ideal, real, strict=True)]
        each = ", ".join(f"{r:.2f}" for r in ratios)
        print(
            f"| {n} | {np.median(ideal):,.0f} | {np.median(real):,.0f} "
            f"| **{np.median(ratios):.2f}x** ({each}) |"
        )
    if args.env_by_env:
        batched = CameraRows.measure
        CameraRows.measure = _one_by_one  # type: ignore[method-assign]
        try:
            for n in args.envs:
                single = rate(n, args.steps, 1, camera=CAMERA)
                print(f"env by env, {n} envs: {single:,.0f} env steps/s")
        finally:
            CameraRows.measure = batched  # type: ignore[method-assign]


if __name__ == "__main__":
    main()
