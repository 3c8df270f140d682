"""The settings of ``ibvs-straight-filtered`` on validation seeds (10,000+), imperfect camera.

    python research/diagnostics/bench_filter_settings.py [--episodes 60]

Prints, for each smoothing and final-approach radius, how many episodes park (2 cm / 2 deg)
through the "all together" camera of the ``imperfect`` suite (principal point (2, -1) px,
focal ratio +1 %, 1 px of noise), and how the others ended.
"""

from __future__ import annotations

import argparse
import itertools
from collections import Counter

from radial_ibvs_agents.analytic.filtered import FilteredPolicy
from radial_ibvs_agents.analytic.ibvs_straight import StraightIBVSPolicy
from radial_ibvs_agents.rollouts import make_env, run_episode
from radial_ibvs_agents.rows import episode_row

CAMERA = {
    "mirror": "A",
    "non_central_offset": 0.01,
    "imperfections": {
        "principal_point_offset": [2.0, -1.0],
        "focal_ratio_error": 0.01,
        "pixel_noise_std": 1.0,
    },
}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--episodes", type=int, default=60)
    args = parser.parse_args()
    print("| smoothing | rotate_radius [m] | parked | ends |")
    print("|---|---|---|---|")
    for smoothing, radius in itertools.product((0.0, 0.7, 0.85, 0.9), (0.02, 0.035, 0.05)):
        policy = FilteredPolicy(StraightIBVSPolicy(rotate_radius=radius), smoothing)
        env = make_env(policy, "random", {"physics": "kinematic", "camera": CAMERA})
        rows = [
            episode_row(run_episode(policy, env, seed=10_000 + k)) for k in range(args.episodes)
        ]
        ends = Counter(r["end"] for r in rows)
        parked = sum(bool(r["success"]) for r in rows)
        print(f"| {smoothing} | {radius} | {parked}/{args.episodes} | {dict(ends)} |", flush=True)


if __name__ == "__main__":
    main()
