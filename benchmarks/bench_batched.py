"""Batched evaluation against one episode at a time: wall time and the policies' compute per step.

Usage: ``python benchmarks/bench_batched.py [--episodes N]``. For each policy, the same
``held-out`` episodes (random rooms, kinematic physics, seeds from 100,000) run as one
benchmark job: one at a time in a scalar env (what the benchmark did), and batched in the
native vector env with one ``predict`` per step for the batch (what it does). Prints the wall
time of each and the policy's compute per robot-step, alone and batched; the rows are the same
(``tests/agents/experiments/test_batched.py``). Run it on a quiet machine: the figures are
wall-clock times.
"""

from __future__ import annotations

import argparse
import platform
import time

import torch

import radial_ibvs_agents.rollouts as rollouts
from radial_ibvs_agents.experiments import jobs
from radial_ibvs_agents.experiments.suites import SUITES

POLICIES = (
    "ibvs",
    "ibvs-current",
    "ibvs-mean",
    "ibvs-straight",
    "ibvs-straight-filtered",
    "pbvs",
    "pbvs-ekf",
    "dagger-student",
)


def run(policy: str, episodes: int, batch: bool) -> tuple[float, float, int]:
    """Wall seconds, compute microseconds per robot-step, and steps of one job."""
    variant = next(v for v in SUITES["held-out"] if v.label == "random rooms")
    job = jobs.Job(policy, variant, episodes)
    saved = rollouts.batch_mode
    if not batch:
        rollouts.batch_mode = lambda p: None  # type: ignore[assignment]
    try:
        start = time.perf_counter()
        result = jobs.run_job(job)
        wall = time.perf_counter() - start
    finally:
        rollouts.batch_mode = saved
    steps = sum(row["steps"] for row in result.rows)
    compute = sum(row["compute_us_per_step"] * row["steps"] for row in result.rows) / steps
    return wall, compute, steps


def main() -> None:
    """Print the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--episodes", type=int, default=100, help="default: %(default)s")
    parser.add_argument("--policies", nargs="+", default=list(POLICIES), help="default: all")
    args = parser.parse_args()
    torch.set_num_threads(1)
    print(f"{platform.processor() or platform.machine()}, torch threads 1, {args.episodes} "
          "held-out episodes per policy (one benchmark job)")  # fmt: skip
    print(
        f"{'policy':<24}{'steps':>7}{'alone s':>9}{'batched s':>11}{'speed-up':>10}"
        f"{'us/step alone':>15}{'us/step batched':>17}"
    )
    for policy in args.policies:
        wall_alone, us_alone, steps = run(policy, args.episodes, batch=False)
        wall_batch, us_batch, _ = run(policy, args.episodes, batch=True)
        print(
            f"{policy:<24}{steps:>7}{wall_alone:>9.1f}{wall_batch:>11.1f}"
            f"{wall_alone / wall_batch:>9.1f}x{us_alone:>15.0f}{us_batch:>17.1f}"
        )


if __name__ == "__main__":
    main()
