"""A compact results table from benchmark rows: policies as columns, the planner's limit first.

    radial-ibvs benchmark --out outputs/benchmark
    python benchmarks/results_table.py outputs/benchmark/episodes.json \
        --suites held-out obstacles cross-camera paper paper-lab imperfect

Several runs' rows can be joined (``ROWS ROWS ...``), and a model directory shown under the
name it ships as (``--rename outputs/sweep/approach/seed-0=ppo-student``).

Each cell is the success rate at 2 cm / 2 deg with its 95 % Wilson interval; the last rows
say how the failed episodes ended (collision / time-out / lost) for each policy.
"""

from __future__ import annotations

import argparse
import json
from collections import Counter, defaultdict
from pathlib import Path

from agents.experiments.evaluate import wilson_interval

DEFAULT_POLICIES = [
    "planner",
    "ibvs",
    "ibvs-backward",
    "ibvs-straight",
    "ibvs-straight-filtered",
    "oracle",
    "oracle-backward",
    "ppo-residual",
]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("rows", type=Path, nargs="+", help="episodes.json of benchmark runs")
    parser.add_argument("--suites", nargs="+", help="default: every suite in the rows")
    parser.add_argument("--policies", nargs="+", default=DEFAULT_POLICIES)
    parser.add_argument(
        "--rename", nargs="+", default=[], metavar="OLD=NEW", help="show policy OLD as NEW"
    )
    args = parser.parse_args()
    if bad := [item for item in args.rename if "=" not in item]:
        parser.error(f"--rename takes OLD=NEW, got {bad}")
    renames = dict(item.split("=", 1) for item in args.rename)
    rows = [row for path in args.rows for row in json.loads(path.read_text())]
    for row in rows:
        row["policy"] = renames.get(row["policy"], row["policy"])
    cells: dict[tuple[str, str], dict[str, list[dict]]] = defaultdict(lambda: defaultdict(list))
    order: list[tuple[str, str]] = []
    for row in rows:
        key = (row["suite"], row["variant"])
        if args.suites and row["suite"] not in args.suites:
            continue
        if key not in cells:
            order.append(key)
        cells[key][row["policy"]].append(row)
    if args.suites:
        order.sort(key=lambda k: args.suites.index(k[0]))
    policies = [p for p in args.policies if any(p in cells[k] for k in order)]
    print("| suite: variant | episodes | " + " | ".join(f"`{p}`" for p in policies) + " |")
    print("|---|---|" + "---|" * len(policies))
    for key in order:
        n = max(len(v) for v in cells[key].values())
        out = []
        for policy in policies:
            episodes = cells[key].get(policy, [])
            if not episodes:
                out.append("-")
                continue
            wins = sum(bool(r["success"]) for r in episodes)
            lo, hi = wilson_interval(wins, len(episodes))
            rate = f"{100 * wins / len(episodes):.0f}"
            out.append(f"{rate} ({100 * lo:.0f}-{100 * hi:.0f})" if len(episodes) >= 20 else rate)
        print(f"| {key[0]}: {key[1]} | {n} | " + " | ".join(out) + " |")
    print()
    print("| failures (collision / time-out / lost) | | " + " | ".join(policies) + " |")
    for key in order:
        out = []
        for policy in policies:
            ends = Counter(str(r.get("end")) for r in cells[key].get(policy, []))
            out.append(f"{ends['collision']} / {ends['time-out']} / {ends['lost']}")
        print(f"| {key[0]}: {key[1]} | | " + " | ".join(out) + " |")


if __name__ == "__main__":
    main()
