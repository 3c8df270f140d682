"""The settings of ``ekf-planner`` on validation seeds (10,000+), ideal and imperfect cameras.

    python research/diagnostics/ekf_planner_settings.py [--episodes 100] [--settings NAME ...]

Prints, for each setting, how many episodes park (2 cm / 2 deg held 1 s) through the ideal
camera of the ``held-out`` suite and three cameras of the ``imperfect`` suite (1 px of noise;
principal point (2, -1) px with focal ratio +1 %; both, the goal averaged over 30 frames), on
the validation rooms (seeds from 10,000: what settings may be chosen on), how the others ended
and the mean episode length. The settings: the planner all the way (``law_radius`` 0), the
law within 1 m (the default), and "stop and look" with and without a correction after it.
"""

from __future__ import annotations

import argparse
import time
from collections import Counter
from typing import Any

import numpy as np

from radial_ibvs_agents.analytic.ekf_planner import EKFPlanner
from radial_ibvs_agents.experiments.suites import SUITES
from radial_ibvs_agents.rollouts import run_episodes

VALIDATION_SEED = 10_000
SETTINGS: dict[str, dict[str, Any]] = {
    "the planner all the way": {"law_radius": 0.0},
    "the law within 1 m (the default)": {},
    "stop and look, then correct": {"look_steps": 10},
    "stop and look, the law after it": {"look_steps": 10, "correct": False},
}
VARIANTS = (
    ("held-out", "random rooms"),
    ("imperfect", "noise 1 px"),
    ("imperfect", "pp (2, -1) px, fy +1 %"),
    ("imperfect", "all together, goal over 30 frames"),
)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--episodes", type=int, default=100)
    parser.add_argument("--settings", nargs="+", choices=sorted(SETTINGS), default=list(SETTINGS))
    args = parser.parse_args()
    seeds = [VALIDATION_SEED + k for k in range(args.episodes)]
    print("| settings | suite: variant | parked | ends | mean steps | wall |")
    print("|---|---|---|---|---|---|")
    for name in args.settings:
        for suite, label in VARIANTS:
            variant = next(v for v in SUITES[suite] if v.label == label)
            start = time.perf_counter()
            logs = run_episodes(
                EKFPlanner(**SETTINGS[name]), seeds, variant.scenario, variant.overrides
            )
            ends = Counter(log.end for log in logs)
            parked = ends.pop("success", 0)
            steps = np.mean([log.steps for log in logs])
            wall = time.perf_counter() - start
            print(
                f"| {name} | {suite}: {label} | {parked}/{len(seeds)} | {dict(ends)} | "
                f"{steps:.0f} | {wall:.0f} s |",
                flush=True,
            )


if __name__ == "__main__":
    main()
