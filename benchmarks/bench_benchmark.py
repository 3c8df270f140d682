"""The whole benchmark's wall time, per suite, and each policy's compute per step.

Usage: ``python benchmarks/bench_benchmark.py [--workers 2] [--out outputs/full]``, on a quiet
machine (the figures are wall-clock times). Runs ``radial-ibvs benchmark --workers N --out OUT
--fresh --no-progress`` (every suite, every policy: the default benchmark) as a user would,
times it, and prints:

- the wall time of the whole command (start-up, loading the models and writing the outputs
  included);
- ``OUT/timings.md``: each suite's episodes and worker-seconds (every job is timed in its
  worker), and the wall time they imply with N workers;
- each policy's compute per robot-step in the rows (the median over the benchmark's jobs) and
  how many robots one call served.

``--suites`` and ``--policies`` narrow it (for a quick look; the figures of
``docs/benchmarks.md`` are of the whole default benchmark).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import time
from collections import defaultdict
from pathlib import Path

import numpy as np


def main() -> None:
    """Run the benchmark and print the figures."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--out", default="outputs/full")
    parser.add_argument("--suites", nargs="+", default=None)
    parser.add_argument("--policies", nargs="+", default=None)
    args = parser.parse_args()
    if args.workers < 1:
        parser.error(f"--workers must be >= 1, got {args.workers}")
    command = [
        sys.executable,
        "-m",
        "radial_ibvs_agents.cli",
        "benchmark",
        "--workers",
        str(args.workers),
    ]
    command += ["--out", args.out, "--fresh", "--no-progress"]
    if args.suites:
        command += ["--suites", *args.suites]
    if args.policies:
        command += ["--policies", *args.policies]
    shown = " ".join(["radial-ibvs", *command[3:]])
    print(f"# the benchmark: {platform.machine()}, {os.cpu_count()} CPUs, {time.ctime()}")
    print(f"$ {shown}")
    start = time.perf_counter()
    done = subprocess.run(command, stdout=subprocess.DEVNULL, check=False)
    wall = time.perf_counter() - start
    if done.returncode != 0:
        sys.exit(f"the benchmark failed (exit status {done.returncode})")
    out = Path(args.out)
    rows = json.loads((out / "episodes.json").read_text())
    policies = sorted({row["policy"] for row in rows})
    print(
        f"\n**{wall:.0f} s** of wall time ({wall / 60:.1f} min): {len(policies)} policies, "
        f"{len(rows):,} episodes, {args.workers} workers\n"
    )
    print((out / "timings.md").read_text())
    compute: dict[str, list[float]] = defaultdict(list)
    batch: dict[str, list[int]] = defaultdict(list)
    for row in rows:
        compute[row["policy"]].append(float(row["compute_us_per_step"]))
        batch[row["policy"]].append(int(row.get("compute_batch") or 1))
    print("| policy | compute per robot-step (median of its episodes) | robots per call |")
    print("|---|---:|---:|")
    for policy in sorted(compute, key=lambda p: -float(np.median(compute[p]))):
        print(
            f"| `{policy}` | {np.median(compute[policy]):.0f} us "
            f"| {int(np.median(batch[policy]))} (median), {max(batch[policy])} (largest) |"
        )


if __name__ == "__main__":
    main()
