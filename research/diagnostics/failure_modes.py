"""How the image-only policies fail: where the pose estimate's error goes near the goal, and how
each policy's failed episodes end.

    python research/diagnostics/failure_modes.py [--episodes 60] [--suite imperfect]
        [--variant LABEL] [--policies ekf-planner pbvs-ekf dagger-student ...]

On validation seeds (from 10,000), in one variant of a benchmark suite (default: ``imperfect``,
all together, the goal over 30 frames), prints two tables:

- **The pose estimate against the distance to the goal**, for the policies that filter the goal's
  pose (``pbvs-ekf``, ``ekf-planner``): the median and 90th percentile of the position error
  (centimetres) and heading error (degrees) of the filter's pose and of the pose solved from the
  frame alone, by the true distance to the goal. The true pose is read from the env, here only.
- **How the failures end**, for every policy: per end (collision, time-out, lost), the number of
  episodes and the medians of the final distance (cm), final heading error (deg), final speed
  (m/s, from the last two poses) and the nearest approach (cm): a time-out that came within 2 cm
  then wandered, or one that never came near.
"""

from __future__ import annotations

import argparse
import itertools
import math
from collections import defaultdict
from typing import Any

import numpy as np

from radial_ibvs_agents import make_policy
from radial_ibvs_agents.experiments.suites import SUITES
from radial_ibvs_agents.rollouts import make_env, run_episodes
from radial_ibvs_gym.geometry import pose_in_frame

VALIDATION_SEED = 10_000
BINS = (0.0, 0.03, 0.1, 0.3, 1.0, math.inf)  # metres from the goal


def _filtered(state: Any) -> np.ndarray | None:
    """The filter's goal pose in the robot's frame, ``(3,)``, from a policy's state."""
    filters = getattr(state, "filters", state)
    mean, started = getattr(filters, "mean", None), getattr(filters, "started", None)
    if mean is None or started is None or not bool(np.asarray(started)[0]):
        return None
    return np.asarray(mean)[0]


def pose_errors(name: str, variant: Any, seeds: list[int]) -> list[tuple[float, ...]]:
    """Per frame: true distance, filter's and solve's position and heading errors (m, rad)."""
    policy = make_policy(name)
    env = make_env(policy, variant.scenario, variant.overrides)
    rows: list[tuple[float, ...]] = []
    for seed in seeds:
        obs, _ = env.reset(seed=seed)
        state: Any = None
        for t in range(600):
            action, state = policy.predict(obs, state, episode_start=np.array([t == 0]))
            base: Any = env.unwrapped
            truth = np.array(pose_in_frame(base.world.pose, base.episode.goal))
            estimate = _filtered(state)
            solved, valid = policy.goal_pose({k: np.asarray(v)[None] for k, v in obs.items()})
            if estimate is not None and bool(valid[0]):
                rows.append(
                    (
                        float(np.hypot(*truth[:2])),
                        float(np.hypot(*(estimate[:2] - truth[:2]))),
                        abs(math.remainder(float(estimate[2] - truth[2]), 2 * math.pi)),
                        float(np.hypot(*(solved[0, :2] - truth[:2]))),
                        abs(math.remainder(float(solved[0, 2] - truth[2]), 2 * math.pi)),
                    )
                )
            obs, _, terminated, truncated, _ = env.step(action)
            if terminated or truncated:
                break
    return rows


def print_pose_table(name: str, rows: list[tuple[float, ...]]) -> None:
    """Print the pose errors of one policy, binned by the true distance to the goal."""
    table = np.array(rows)
    print(f"\n{name}: the goal's pose in the robot's frame, error by distance to the goal")
    print(
        "| distance | frames | filter: cm (median / p90) | filter: deg | solve: cm | solve: deg |"
    )
    print("|---|---|---|---|---|---|")
    for lo, hi in itertools.pairwise(BINS):
        part = table[(table[:, 0] >= lo) & (table[:, 0] < hi)]
        if not len(part):
            continue

        def cell(column: int, scale: float, part: np.ndarray = part) -> str:
            values = part[:, column] * scale
            return f"{np.median(values):.2f} / {np.percentile(values, 90):.2f}"

        label = f"{lo * 100:.0f}-{hi * 100:.0f} cm" if math.isfinite(hi) else f"> {lo:.0f} m"
        print(
            f"| {label} | {len(part)} | {cell(1, 100)} | {cell(2, 180 / math.pi)} | "
            f"{cell(3, 100)} | {cell(4, 180 / math.pi)} |"
        )


def failure_ends(name: str, variant: Any, seeds: list[int]) -> None:
    """Print how the failed episodes of one policy end."""
    logs = run_episodes(make_policy(name), seeds, variant.scenario, variant.overrides)
    ends: dict[str, list[tuple[float, float, float, float]]] = defaultdict(list)
    for log in logs:
        if log.end == "success":
            continue
        goal = np.asarray(log.info["goal_pose"], dtype=np.float64)
        rel = np.array([pose_in_frame(goal, pose) for pose in log.poses])
        distance = np.hypot(rel[:, 0], rel[:, 1])
        step = np.hypot(*(log.poses[-1][:2] - log.poses[-2][:2])) if len(log.poses) > 1 else 0.0
        dt = float(log.times[1] - log.times[0]) if len(log.times) > 1 else 0.1
        ends[log.end].append(
            (
                100 * float(distance[-1]),
                abs(math.degrees(float(rel[-1, 2]))),
                float(step) / dt,
                100 * float(distance.min()),
            )
        )
    parked = sum(log.end == "success" for log in logs)
    print(f"| {name} | parked {parked}/{len(logs)} | | | | |")
    for end, values in sorted(ends.items()):
        med = np.median(np.array(values), axis=0)
        print(
            f"| | {end}: {len(values)} | {med[0]:.1f} | {med[1]:.1f} | {med[2]:.3f} | "
            f"{med[3]:.1f} |"
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--episodes", type=int, default=60)
    parser.add_argument("--suite", default="imperfect")
    parser.add_argument("--variant", default="all together, goal over 30 frames")
    parser.add_argument(
        "--policies",
        nargs="+",
        default=["ekf-planner", "pbvs-ekf", "ibvs-straight-filtered", "dagger-student"],
    )
    args = parser.parse_args()
    if args.suite not in SUITES:
        parser.error(f"--suite {args.suite!r} is not a suite: {list(SUITES)}")
    labels = [v.label for v in SUITES[args.suite]]
    if args.variant not in labels:
        parser.error(f"--variant {args.variant!r} is not a variant of {args.suite}: {labels}")
    variant = next(v for v in SUITES[args.suite] if v.label == args.variant)
    seeds = [VALIDATION_SEED + k for k in range(args.episodes)]
    print(f"{args.suite}: {args.variant}; {args.episodes} episodes (seeds from 10,000)")
    for name in args.policies:
        if hasattr(make_policy(name), "goal_pose"):
            print_pose_table(name, pose_errors(name, variant, seeds))
    print("\nHow the failures end (medians):")
    print(
        "| policy | end | final distance [cm] | final heading [deg] | final speed [m/s] "
        "| nearest [cm] |"
    )
    print("|---|---|---|---|---|---|")
    for name in args.policies:
        failure_ends(name, variant, seeds)


if __name__ == "__main__":
    main()
