"""The Ray backend against the local process pool, and the wall time of a large study.

Usage: ``python benchmarks/bench_backends.py [--episodes 40] [--workers 2]``.

1. The same benchmark jobs (four analytic policies on the ``paper`` and ``random`` suites,
   ``--episodes`` per variant, 20-episode chunks) on ``--backend local`` and ``--backend ray``
   (a private instance with ``--workers`` CPUs): wall time, Ray's start-up apart, and the
   ratio. The rows are checked equal.
2. The cost of one episode of each suite variant (one process, a few episodes each, for the
   analytic IBVS), and from it the expected wall time of a 10-seed study: 10 trained models on
   every suite variant at its default episodes, plus 10 training runs of 30 minutes, on 1, 4
   and 16 machines like this one (``--workers`` cores each), with the overhead ratio measured.
"""

from __future__ import annotations

import argparse
import math
import os
import platform
import time

POLICIES = ["ibvs", "oracle", "ibvs-backward", "oracle-backward"]


def _strip(results) -> list:
    return [
        {k: v for k, v in row.items() if k != "compute_us_per_step"}
        for r in results
        for row in r.rows
    ]


def overhead(episodes: int, workers: int) -> float:
    """Run the same jobs locally and on Ray; print and return the wall-time ratio."""
    from radial_ibvs_agents.experiments.backends import RayBackend
    from radial_ibvs_agents.experiments.benchmark import run_benchmark

    kwargs = {"episodes": episodes, "workers": workers, "progress": False}
    start = time.perf_counter()
    local = run_benchmark(POLICIES, ["paper", "random"], backend="local", **kwargs)
    t_local = time.perf_counter() - start
    start = time.perf_counter()
    backend = RayBackend(num_cpus=workers)
    t_init = time.perf_counter() - start
    start = time.perf_counter()
    ray_results = run_benchmark(POLICIES, ["paper", "random"], backend=backend, **kwargs)
    t_ray = time.perf_counter() - start
    backend.close()
    chunks = sum(math.ceil(r.job.episodes / 20) for r in local)
    same = _strip(local) == _strip(ray_results)
    print(f"1. {len(POLICIES)} policies x (paper: 2 variants, random) x {episodes} episodes "
          f"= {chunks} chunks, {workers} workers")  # fmt: skip
    print(f"   local pool     {t_local:7.1f} s")
    print(f"   Ray            {t_ray:7.1f} s  (+ {t_init:.1f} s to start the private instance)")
    print(f"   ratio Ray / local: {t_ray / t_local:.3f} (with start-up: "
          f"{(t_ray + t_init) / t_local:.3f}); rows equal: {same}")  # fmt: skip
    return t_ray / t_local


def study(workers: int, ratio: float, probe: int) -> None:
    """Per-variant episode cost (one process) and the 10-seed study on 1, 4, 16 machines."""
    from radial_ibvs_agents.experiments.jobs import Job, run_job
    from radial_ibvs_agents.experiments.suites import SUITES

    print(f"\n2. seconds per episode (ibvs, one process, {probe} episodes per variant)")
    total = 0.0
    chunk_costs = []
    for suite, variants in SUITES.items():
        for variant in variants:
            start = time.perf_counter()
            run_job(Job("ibvs", variant, probe, 0))
            per_episode = (time.perf_counter() - start) / probe
            total += per_episode * variant.episodes
            n_chunks = math.ceil(variant.episodes / 20)
            chunk_costs += [per_episode * variant.episodes / n_chunks] * n_chunks
            print(f"   {suite:12s} {variant.label:28s} {per_episode:6.2f} s/ep x "
                  f"{variant.episodes} episodes")  # fmt: skip
    seeds, train_min = 10, 30.0
    eval_cpu_s = seeds * total
    print(f"\n   one model on every suite: {total / 60:.1f} CPU-min, "
          f"{len(chunk_costs)} chunks; 10 models: {eval_cpu_s / 3600:.2f} CPU-h")  # fmt: skip
    print(f"   10 training seeds x {train_min:.0f} min on one core each: "
          f"{seeds * train_min / 60:.1f} CPU-h")  # fmt: skip
    print("\n| machines | cores | training (10 seeds) | evaluation (10 models x all suites) "
          "| total |")  # fmt: skip
    print("|---|---|---|---|---|")
    for machines in (1, 4, 16):
        cores = machines * workers
        train_wall = math.ceil(seeds / cores) * train_min
        longest = max(chunk_costs)
        eval_wall = max(eval_cpu_s * ratio / cores, longest) / 60
        print(f"| {machines} | {cores} | {train_wall:.0f} min | {eval_wall:.0f} min "
              f"| {train_wall + eval_wall:.0f} min |")  # fmt: skip


def main() -> None:
    """Print the figures."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--episodes", type=int, default=40)
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 2)
    parser.add_argument("--probe", type=int, default=2, help="episodes per variant in part 2")
    args = parser.parse_args()
    print(f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
          f"Python {platform.python_version()}\n")  # fmt: skip
    ratio = overhead(args.episodes, args.workers)
    study(args.workers, ratio, args.probe)


if __name__ == "__main__":
    main()
