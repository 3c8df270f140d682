"""A shipped policy's compute per action, alone and beside busy processes.

Usage: ``python benchmarks/bench_policy_threads.py [--calls 2000] [--busy 0 1 2]``.

Each shipped model computes one robot's action ``--calls`` times (``predict`` on one
observation, the way a robot calls it); the table gives the median and the 90th percentile in
milliseconds, with ``--busy`` other processes spinning on the cores meanwhile. "default" is what
a user gets: the policy runs a small batch on one torch thread and restores the caller's count
(:mod:`radial_ibvs_agents.learned.files.threads`); "torch's threads" is the call with torch's
own count (a thread per core), as before that rule.
"""

from __future__ import annotations

import argparse
import multiprocessing as mp
import platform
import time
from typing import Any

import gymnasium as gym
import numpy as np
import torch

import radial_ibvs_gym  # noqa: F401  (registers the environments)
from radial_ibvs_agents import load
from radial_ibvs_agents.learned.files import threads

MODELS = ("dagger-student",)


def _spin(stop: Any) -> None:
    """Keep one core busy until ``stop`` is set."""
    x = 0
    while not stop.is_set():
        for _ in range(100_000):
            x += 1


def _latencies_ms(policy: Any, obs: dict[str, np.ndarray], calls: int) -> np.ndarray:
    for _ in range(50):  # warm up
        policy.predict(obs)
    out = np.empty(calls)
    for k in range(calls):
        start = time.perf_counter()
        policy.predict(obs)
        out[k] = time.perf_counter() - start
    return 1e3 * out


def main() -> None:
    """Print the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--calls", type=int, default=2000)
    parser.add_argument("--busy", type=int, nargs="+", default=[0, 1, 2])
    args = parser.parse_args()
    print(
        f"# {platform.processor() or platform.machine()}, {mp.cpu_count()} cores, torch "
        f"{torch.__version__} ({torch.get_num_threads()} threads by default)"
    )
    print("| model | busy processes | threads | median ms | p90 ms |")
    print("|---|---:|---|---:|---:|")
    small = threads.SMALL_BATCH
    for name in MODELS:
        policy = load(name)
        env = gym.make("RadialIBVS/Parking-v0", **policy.env_kwargs)
        obs, _ = env.reset(seed=0)
        for busy in args.busy:
            stop = mp.Event()
            spinners = [mp.Process(target=_spin, args=(stop,)) for _ in range(busy)]
            for p in spinners:
                p.start()
            try:
                for label, batch in (("default", small), ("torch's threads", 0)):
                    threads.SMALL_BATCH = batch  # 0: no batch is small, torch's count stays
                    ms = _latencies_ms(policy, obs, args.calls)
                    p50, p90 = np.percentile(ms, [50, 90])
                    print(f"| {name} | {busy} | {label} | {p50:.3f} | {p90:.3f} |")
            finally:
                threads.SMALL_BATCH = small
                stop.set()
                for p in spinners:
                    p.join()


if __name__ == "__main__":
    main()
