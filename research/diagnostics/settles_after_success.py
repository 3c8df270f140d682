"""Does a policy stay parked once the episode counts it a success, or is it passing through?

Usage::

    python research/diagnostics/settles_after_success.py [--policies ibvs-straight ...] \
        [--episodes 100] [--after 50] [--variant "imperfect: noise 1 px"]

It judges by the older rule on purpose (``success_hold_steps=1``): the env ends an episode at
the first step whose true pose is within the tolerance (2 cm / 2 deg), a fact a real robot
would not be told. (The envs' own rule is now a park, the pose held 1 s, which counts no pass;
this asks what happens after the first step within the window.) A policy that stops at the
goal is parked there; one that keeps moving may only be passing through, and a learned policy
rewarded on that first step may learn to wander near the goal until the window catches it. Here each
successful episode goes on for ``--after`` more control steps (stepping the unwrapped env, so
neither the success nor the time limit stops it), with the policy acting as before, and this
prints, per policy: the episodes parked, and of those the share still within 2 cm / 2 deg and
within 5 cm / 5 deg at the end, the median distance from the goal then, and the median path
driven after the success (metres: near zero for a policy that stops).
"""

from __future__ import annotations

import argparse
import math
from typing import Any

import numpy as np

from radial_ibvs_agents import make_policy
from radial_ibvs_agents.experiments.suites import SUITES
from radial_ibvs_agents.rollouts import make_env
from radial_ibvs_agents.rows import JUDGING


def _variant(name: str) -> Any:
    suite, label = name.split(": ", 1)
    return next(v for v in SUITES[suite] if v.label == label)


def settle(policy_name: str, variant: Any, episodes: int, after: int) -> dict[str, float]:
    """Run the episodes; return what the policy does after each success."""
    policy = make_policy(policy_name)
    overrides = {**JUDGING, **variant.overrides, "success_hold_steps": 1}  # the first step
    env = make_env(policy, variant.scenario, overrides)
    u: Any = env.unwrapped
    parked = 0
    final = []  # (position error m, heading error deg) after the extra steps
    paths = []
    for k in range(episodes):
        obs, info = env.reset(seed=variant.seed_offset + k)
        state, start = None, np.ones(1, dtype=bool)
        done = False
        while not done:
            action, state = policy.predict(obs, state, start, deterministic=True)
            start = np.zeros(1, dtype=bool)
            obs, _, terminated, truncated, info = env.step(action)
            done = terminated or truncated
        if not info.get("is_success"):
            continue
        parked += 1
        path, pose = 0.0, np.array(info["robot_pose"], dtype=np.float64)
        for _ in range(after):
            action, state = policy.predict(obs, state, start, deterministic=True)
            obs, _, _, _, info = u.step(action)
            now = np.array(info["robot_pose"], dtype=np.float64)
            path += math.hypot(*(now[:2] - pose[:2]))
            pose = now
            if info.get("collision"):
                break
        final.append((float(info["position_error_m"]), float(info["heading_error_deg"])))
        paths.append(path)
    env.close()
    errors = np.array(final).reshape(-1, 2)
    within = (errors[:, 0] <= 0.02) & (errors[:, 1] <= 2.0)
    near = (errors[:, 0] <= 0.05) & (errors[:, 1] <= 5.0)
    return {
        "episodes": episodes,
        "parked": parked,
        "still_2cm": float(within.mean()) if parked else math.nan,
        "still_5cm": float(near.mean()) if parked else math.nan,
        "median_error_cm": 100 * float(np.median(errors[:, 0])) if parked else math.nan,
        "median_path_m": float(np.median(paths)) if parked else math.nan,
    }


def main() -> None:
    """Print the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--policies", nargs="+", default=["ibvs-straight", "pbvs", "dagger-student"]
    )
    parser.add_argument("--episodes", type=int, default=100)
    parser.add_argument("--after", type=int, default=50, help="control steps after the success")
    parser.add_argument("--variant", default="held-out: random rooms", help="'SUITE: VARIANT'")
    args = parser.parse_args()
    variant = _variant(args.variant)
    print(f"{args.variant}, {args.episodes} episodes, {args.after} steps after each success")
    print(
        "| policy | parked | still within 2 cm / 2 deg | within 5 cm / 5 deg | median error "
        "after [cm] | median path after [m] |"
    )
    print("|---|---|---|---|---|---|")
    for name in args.policies:
        r = settle(name, variant, args.episodes, args.after)
        print(
            f"| {name} | {r['parked']} | {r['still_2cm']:.0%} | {r['still_5cm']:.0%} | "
            f"{r['median_error_cm']:.1f} | {r['median_path_m']:.2f} |"
        )


if __name__ == "__main__":
    main()
