"""Cost per call of the maths layer (a script that prints figures, not a timed test).

Usage: ``python benchmarks/bench_maths.py`` (or ``make bench``). Prints, for this machine:
- exact forward projection (root-find of the law of reflection) for 1, 9 and 10,000 points,
  central and non-central mirror A;
- the full feature + interaction-matrix computation (x_n, c_ij, L_cij, alpha_m, L_alpha_m)
  for 9 points, one scene and a batch of 1,000 scenes.
"""

from __future__ import annotations

import platform
import timeit
from collections.abc import Callable

import numpy as np

from radial_ibvs_gym.camera import paper_camera, radial_points
from radial_ibvs_gym.features import compute_features, virtual_point_weights


def per_call(fn: Callable[[], object], min_time: float = 0.5) -> float:
    """Best-of-5 seconds per call, each repeat running at least ``min_time`` seconds."""
    timer = timeit.Timer(fn)
    number, _ = timer.autorange()
    number = max(number, int(number * min_time / 0.2))
    return min(timer.repeat(repeat=5, number=number)) / number


def fmt(seconds: float) -> str:
    """Seconds as a human-readable duration."""
    if seconds < 1e-3:
        return f"{seconds * 1e6:8.1f} us"
    return f"{seconds * 1e3:8.2f} ms"


def random_scene(rng: np.random.Generator, shape: tuple[int, ...]) -> np.ndarray:
    """Points all around the camera: 1-15 m away, from 1.8 m below to 0.7 m above it."""
    r = rng.uniform(1.0, 15.0, shape)
    phi = rng.uniform(-np.pi, np.pi, shape)
    z = rng.uniform(-1.8, 0.7, shape)
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=-1)


def main() -> None:
    """Print the benchmark table."""
    rng = np.random.default_rng(0)
    print(f"# maths layer: {platform.processor() or platform.machine()}, numpy {np.__version__}")
    print("\n## exact forward projection (mirror A, law of reflection solved per point)")
    print(f"{'configuration':<14}{'points':>8}{'per call':>13}{'per point':>13}")
    for label, offset in (("central", 0.0), ("non-central", 0.01)):
        cam = paper_camera("A", non_central_offset=offset)
        for n in (1, 9, 10_000):
            pts = random_scene(rng, (n,))
            t = per_call(lambda cam=cam, pts=pts: cam.forward(pts))
            print(f"{label:<14}{n:>8}{fmt(t):>13}{fmt(t / n):>13}")

    print("\n## features + interaction matrices (9 points: 36 c_ij, alpha_m, L_c, L_alpha_m)")
    goal = random_scene(rng, (9,))
    a = virtual_point_weights(radial_points(goal).x_n)

    def full(points: np.ndarray) -> object:
        x_n, d, z_n = radial_points(points)
        return compute_features(x_n, d, z_n, a)

    print(f"{'scenes':>8}{'per call':>13}{'per scene':>13}")
    for batch in (None, 1000):
        pts = random_scene(rng, (9,) if batch is None else (batch, 9))
        t = per_call(lambda pts=pts: full(pts))
        n = 1 if batch is None else batch
        print(f"{n:>8}{fmt(t):>13}{fmt(t / n):>13}")


if __name__ == "__main__":
    main()
