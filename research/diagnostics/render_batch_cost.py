"""Does rendering a batch of frames in one fused numpy pass beat rendering them one at a time?

Renders 64 views of the paper-sim room (384 px, the pixels suite's size) from random poses, in
batches of B frames through ``OmniRenderer.render_batch`` and one at a time through ``render``,
and prints the milliseconds per frame. Run: ``python research/diagnostics/render_batch_cost.py``.
"""

from __future__ import annotations

import time

import gymnasium as gym
import numpy as np

import radial_ibvs_gym  # noqa: F401  (registers the environments)


def main() -> None:
    env = gym.make(
        "RadialIBVS/Parking-v0",
        scenario="paper-sim",
        physics="kinematic",
        measurement="detected",
        image_size=384,
        beacon_radius=0.1,
    ).unwrapped
    env.reset(seed=0)
    renderer, scene = env._detector.renderers["current"], env._detector.scene
    rng = np.random.default_rng(0)
    poses = np.column_stack([rng.uniform(1, 4, 64), rng.uniform(1, 3, 64), rng.uniform(-3, 3, 64)])
    for _ in range(2):  # the second pass is the one reported
        rows = []
        for b in (1, 2, 8, 32):
            start = time.perf_counter()
            for _ in range(3):
                for i in range(0, 64, b):
                    renderer.render_batch(poses[i : i + b], scene)
            rows.append((b, (time.perf_counter() - start) / (3 * 64)))
        start = time.perf_counter()
        for _ in range(3):
            for pose in poses:
                renderer.render(pose, scene)
        alone = (time.perf_counter() - start) / (3 * 64)
    for b, seconds in rows:
        print(f"batch of {b:2d}: {1e3 * seconds:.2f} ms per frame")
    print(f"one at a time: {1e3 * alone:.2f} ms per frame")


if __name__ == "__main__":
    main()
