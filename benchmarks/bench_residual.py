"""The residual env's speed against the plain vector env it wraps, at the same trajectories.

Usage: ``python benchmarks/bench_residual.py [--envs 256] [--steps 300] [--repeats 3]``.

A residual env (:class:`radial_ibvs_agents.learned.ResidualVecEnv`) steps the native vector env and,
at every step, its base policy (the paper's IBVS) for the whole batch. To time the base policy's
cost and nothing else, both envs run the *same* trajectories:

1. the residual env, with a zero correction (the env receives the base actions), records the
   actions it sends;
2. the plain vector env, seeded the same, replays those actions: the same robots, the same
   episode ends, the same resets.

The ratio ``plain / residual`` of their step times is the one the residual costs; it is printed with
and without the per-episode goal cache
(:class:`radial_ibvs_agents.analytic.ibvs_maths_batch. GoalCache`), beside the plain env stepped
with zero actions (no episode ever ends: the env's own ceiling). Steps per second are env steps
(robots times batched steps); best of ``--repeats``.
"""

from __future__ import annotations

import argparse
import platform
import time
from typing import Any

import numpy as np

from radial_ibvs_agents.analytic import ibvs_maths_batch
from radial_ibvs_agents.learned.networks.residual import ResidualConfig, ResidualVecEnv
from radial_ibvs_agents.learned.training.sb3_vec_env import make_vec_env

ENV_ID = "RadialIBVS/Parking-v0"
#: the env of the residual models (research/configs/ppo_residual.yaml)
ENV_KWARGS: dict[str, Any] = {
    "scenario": "random",
    "physics": "kinematic",
    "obs_mode": "features",
    "goal_depths": True,
    "max_landmarks": 16,
}


class _NoCache:
    """A stand-in for :class:`GoalCache` that computes the goal terms at every call."""

    def terms(self, goal_points: Any, goal_depths: Any) -> Any:
        return ibvs_maths_batch.GoalTerms.of(goal_points, goal_depths)


def run_residual(n_envs: int, steps: int, cache: bool) -> tuple[float, list[np.ndarray]]:
    """Step the residual env with a zero correction; return (seconds, env actions sent)."""
    venv = ResidualVecEnv(
        make_vec_env(ENV_ID, n_envs, seed=0, **ENV_KWARGS), ResidualConfig("ibvs-backward", 0.5)
    )
    if not cache:
        venv.base._batch_goals = _NoCache()
    sent: list[np.ndarray] = []
    inner_step = venv.venv.step_async

    def record(actions: np.ndarray) -> None:
        sent.append(np.array(actions))
        inner_step(actions)

    venv.venv.step_async = record  # type: ignore[method-assign]
    venv.reset()
    zero = np.zeros((n_envs, 2), dtype=np.float32)
    start = time.perf_counter()
    for _ in range(steps):
        venv.step(zero)
    return time.perf_counter() - start, sent


def run_plain(n_envs: int, actions: list[np.ndarray]) -> float:
    """Step the plain vector env (seeded as the residual's) with the given actions; seconds."""
    venv = make_vec_env(ENV_ID, n_envs, seed=0, **ENV_KWARGS)
    venv.reset()
    start = time.perf_counter()
    for action in actions:
        venv.step(action)
    return time.perf_counter() - start


def main() -> None:
    """Print the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--envs", type=int, default=256)
    parser.add_argument("--steps", type=int, default=300)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    n, steps = args.envs, args.steps
    rate = {}
    for cache in (True, False):
        best_res = best_plain = float("inf")
        for _ in range(args.repeats):
            seconds, sent = run_residual(n, steps, cache)
            best_res = min(best_res, seconds)
            best_plain = min(best_plain, run_plain(n, sent))
        rate[cache] = (n * steps / best_res, n * steps / best_plain)
    zero = [np.zeros((n, 2), dtype=np.float32)] * steps
    ceiling = n * steps / min(run_plain(n, zero) for _ in range(args.repeats))
    print(f"# residual env vs plain vector env, {n} envs, {steps} steps, {platform.processor()}")
    print("| env | env steps/s | residual / plain |\n|---|---:|---:|")
    res, plain = rate[True]
    print(f"| plain vector env, the residual's actions replayed | {plain:,.0f} | 1.00x |")
    print(f"| residual env, goal terms cached per episode | {res:,.0f} | {res / plain:.2f}x |")
    res_nc, plain_nc = rate[False]
    print(f"| residual env, goal terms every step | {res_nc:,.0f} | {res_nc / plain_nc:.2f}x |")
    print(f"| plain vector env, zero actions (no episode ends) | {ceiling:,.0f} | - |")


if __name__ == "__main__":
    main()
