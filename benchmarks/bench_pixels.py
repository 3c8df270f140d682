"""Rendering and measurement: cost per frame and accuracy (prints figures; not a timed test).

Usage: ``python benchmarks/bench_pixels.py`` (or ``make bench``). Targets from the issue on
this kind of machine: a 256 x 256 frame in under 5 ms, 84 x 84 in under 1 ms.

``python benchmarks/bench_pixels.py --against DIR`` compares this checkout's renderer and
detector with those of another checkout ``DIR`` (e.g. a ``git worktree`` of an older commit):
both load in one process and run alternately, call by call (in either order in turn), on
the same frames (the start views of ten episodes per scenario and size), so that a box whose
speed drifts slows both alike; it checks that both give the same images and detections, and
prints each one's median time per call and the median of the per-call ratios.
"""

from __future__ import annotations

import argparse
import importlib.util
import platform
import sys
import time
from functools import partial
from pathlib import Path
from types import ModuleType

import gymnasium as gym
import numpy as np

import radial_ibvs_gym  # noqa: F401  (registers the environments)
from radial_ibvs_agents.experiments.pixels import DEGRADED, detection_accuracy
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


def _load(path: Path, name: str) -> ModuleType:
    """Import one module file of another checkout under a name of its own."""
    spec = importlib.util.spec_from_file_location(name, path)
    if spec is None or spec.loader is None:
        sys.exit(f"cannot load {path}")
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


def against(other: Path, calls: int = 30) -> None:
    """Alternate this checkout's renderer and detector with ``other``'s, call by call."""
    from radial_ibvs_gym.vision.detect import fit_mirror_border

    vision = other / "radial_ibvs_gym" / "vision"
    if not (vision / "omni.py").is_file():
        sys.exit(f"--against: no radial_ibvs_gym/vision/omni.py under {other}")
    old_omni = _load(vision / "omni.py", "_other_omni")
    old_detect = _load(vision / "detect.py", "_other_detect")
    print(f"# pixels, this checkout against {other}: {platform.machine()}, numpy {np.__version__}")
    print("| scenario | size | render: this, other, ratio | measure: this, other, ratio |")
    print("|---|---:|---|---|")
    for scenario, radius in (("paper-lab", 0.08), ("paper-sim", 0.1)):
        sc = load_scenario(scenario)
        for size in (84, 256, 384):
            this = OmniRenderer(sc.camera, size, sc.config.camera_height)
            that = old_omni.OmniRenderer(sc.camera, size, sc.config.camera_height)
            times: dict[str, list[float]] = {key: [] for key in ("rn", "ro", "mn", "mo")}
            for seed in range(10):
                episode = sc.sample(np.random.default_rng(seed))
                scene = room_scene(episode.room, episode.landmarks, radius)
                other_scene = old_omni.RoomScene(
                    scene.size, scene.height, scene.beacons, scene.beacon_radius
                )
                pose = episode.start
                image = this.render(pose, scene)
                if not np.array_equal(image, that.render(pose, other_scene)):
                    sys.exit(f"the images differ: {scenario}, {size} px, seed {seed}")
                border = fit_mirror_border(image)
                if border is None:
                    continue
                a, b = measure(image, border=border), old_detect.measure(image, border=border)
                if not np.array_equal(a.centres, b.centres):
                    sys.exit(f"the detections differ: {scenario}, {size} px, seed {seed}")
                pairs = (
                    (
                        ("rn", partial(this.render, pose, scene)),
                        ("ro", partial(that.render, pose, other_scene)),
                    ),
                    (
                        ("mn", partial(measure, image, border=border)),
                        ("mo", partial(old_detect.measure, image, border=border)),
                    ),
                )
                for pair in pairs:  # each pair in turn, its order swapped call by call
                    for i in range(2 * calls):
                        for key, call in pair if i % 2 else pair[::-1]:
                            start = time.perf_counter()
                            call()
                            times[key].append(time.perf_counter() - start)
            t = {key: np.asarray(value) for key, value in times.items()}
            cells = [
                f"{1e6 * np.median(t[n]):.0f} us, {1e6 * np.median(t[o]):.0f} us, "
                f"{np.median(t[n] / t[o]):.2f}"
                for n, o in (("rn", "ro"), ("mn", "mo"))
            ]
            print(f"| {scenario} | {size} | {cells[0]} | {cells[1]} |")


def main() -> None:
    """Print the tables."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--against", type=Path, default=None, metavar="DIR")
    args = parser.parse_args()
    if args.against is not None:
        against(args.against)
        return
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
