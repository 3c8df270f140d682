"""Rendering and measurement: cost per frame and accuracy (prints figures; not a timed test).

Usage: ``python benchmarks/bench_pixels.py`` (or ``make bench``). Targets from the issue on
this kind of machine: a 256 x 256 frame in under 5 ms, 84 x 84 in under 1 ms.
"""

from __future__ import annotations

import platform
import time

import gymnasium as gym
import numpy as np

import radial_ibvs_gym  # noqa: F401  (registers the environments)
from agents.experiments.pixels import DEGRADED, detection_accuracy
from radial_ibvs_gym.scenarios import load_scenario
from radial_ibvs_gym.vision import OmniRenderer
from radial_ibvs_gym.vision.detect import measure
from radial_ibvs_gym.vision.pipeline import room_scene


def per_call_ms(fn, repeat: int = 200) -> float:
    """Median wall time of ``fn()`` over batches, milliseconds."""
    fn()
    times = []
    for _ in range(5):
        start = time.perf_counter()
        for _ in range(repeat // 5):
            fn()
        times.append((time.perf_counter() - start) / (repeat // 5))
    return 1e3 * float(np.median(times))


def env_step_ms(env_id: str, steps: int = 300, **kwargs) -> float:
    """Milliseconds per random-action step (resets included)."""
    env = gym.make(env_id, scenario="paper-lab", physics="kinematic", **kwargs)
    env.reset(seed=0)
    env.action_space.seed(0)
    start = time.perf_counter()
    for _ in range(steps):
        *_, terminated, truncated, _ = env.step(env.action_space.sample())
        if terminated or truncated:
            env.reset()
    return 1e3 * (time.perf_counter() - start) / steps


def main() -> None:
    """Print the tables."""
    print(f"# pixels: {platform.machine()}, numpy {np.__version__}")
    sc = load_scenario("paper-lab")
    episode = sc.sample(np.random.default_rng(0))
    scene = room_scene(episode.room, episode.landmarks, 0.08)
    print(f"{'size':>6}{'precompute [ms]':>17}{'render [ms]':>13}{'measure [ms]':>14}")
    for size in (84, 128, 256, 384, 512):
        start = time.perf_counter()
        renderer = OmniRenderer(sc.camera, size, sc.config.camera_height)
        setup = 1e3 * (time.perf_counter() - start)
        render = per_call_ms(lambda r=renderer: r.render(episode.start, scene))
        image = renderer.render(episode.start, scene)
        detect = per_call_ms(lambda im=image: measure(im), repeat=100)
        print(f"{size:>6}{setup:>17.1f}{render:>13.2f}{detect:>14.2f}")
    print()
    print("env step, paper-lab, kinematic, random actions [ms]:")
    print(f"  Parking-v0 ideal points            {env_step_ms('RadialIBVS/Parking-v0'):.2f}")
    detected = env_step_ms("RadialIBVS/Parking-v0", measurement="detected")
    print(f"  Parking-v0 detected points (256)   {detected:.2f}")
    print(f"  ParkingImage-v0 (84 x 84)          {env_step_ms('RadialIBVS/ParkingImage-v0'):.2f}")
    print()
    print("detection accuracy, paper-lab, 50 start poses, 256 px, 8 cm beacons:")
    for label, quality in (("clean", None), ("noise 6, blur 0.8, exposure 0.7", DEGRADED)):
        a = detection_accuracy(n_images=50, quality=quality)
        print(
            f"  {label:<33} found {100 * a['detected']:.1f} %, spurious {a['spurious']:.2f}/image,"
            f" error median {a['median_px']:.3f} / p95 {a['p95_px']:.3f} / max "
            f"{a['max_px']:.3f} px, principal point {a['principal_point_px']:.3f} px, "
            f"rho_f {a['rho_f_error']:.4f}"
        )


if __name__ == "__main__":
    main()
