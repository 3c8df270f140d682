"""The IBVS's final-approach radius: calibration robustness against noise robustness.

Usage: ``python benchmarks/bench_final_approach.py [RADIUS ...]`` (metres; default 0.02 0.1 0.2).
Within ``rotate_radius`` of the estimated goal the IBVS stops steering with eq. (38) (singular
at the goal) and makes a final approach. A principal-point error biases the estimated
direction to the goal, and near the goal eq. (38) then circles; an earlier final approach
avoids it, but makes the robot commit to noisy estimates sooner. Prints successes (2 cm / 2 deg
unless said) and the median time to park, kinematic backend, seeds 0..n-1.
"""

from __future__ import annotations

import sys
from typing import Any

import gymnasium as gym
import numpy as np

import radial_ibvs_gym  # noqa: F401  (registers the environments)
from radial_ibvs_agents import IBVSPolicy
from radial_ibvs_agents.rollouts import run_episode


def _camera(**imperfections: Any) -> dict[str, Any]:
    return {"camera": {"mirror": "A", "non_central_offset": 0.01, "imperfections": imperfections}}


CASES: dict[str, tuple[str, int, dict[str, Any]]] = {
    "paper": ("paper-sim", 4, {}),
    "paper 1 cm / 0.5 deg": (
        "paper-sim",
        4,
        {"success_position_m": 0.01, "success_heading_deg": 0.5},
    ),
    "pp (2, -1) px": ("paper-sim", 8, _camera(principal_point_offset=[2.0, -1.0])),
    "pp (5, -3) px": ("paper-sim", 8, _camera(principal_point_offset=[5.0, -3.0])),
    "noise 1 px": ("paper-sim", 8, _camera(pixel_noise_std=1.0)),
    "noise 2 px": ("paper-sim", 8, _camera(pixel_noise_std=2.0)),
    "fy +2 %": ("paper-sim", 8, _camera(focal_ratio_error=0.02)),
    "random rooms": ("random", 100, {}),
}


def run(policy: IBVSPolicy, scenario: str, episodes: int, overrides: dict[str, Any]) -> str:
    """Successes and the median time to park of one case."""
    env = gym.make(
        "RadialIBVS/Parking-v0",
        scenario=scenario,
        physics="kinematic",
        goal_depths=True,
        **overrides,
    )
    parked, times = 0, []
    for k in range(episodes):
        options = {"task": k % 4} if scenario == "paper-sim" else None
        log = run_episode(policy, env, seed=k, options=options)
        if log.info["is_success"]:
            parked += 1
            times.append(0.1 * len(log.actions))
    median = f"{np.median(times):.1f} s" if times else "-"
    return f"{parked}/{episodes} ({median})"


def main() -> None:
    """Print one row per final-approach radius."""
    radii = [float(a) for a in sys.argv[1:]] or [0.02, 0.1, 0.2]
    print("rotate_radius [m] | " + " | ".join(CASES))
    for radius in radii:
        policy = IBVSPolicy(rotate_radius=radius)
        cells = [run(policy, *case) for case in CASES.values()]
        print(f"{radius} | " + " | ".join(cells))


if __name__ == "__main__":
    main()
