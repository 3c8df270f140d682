"""Success across training seeds from benchmark rows: IQM with stratified-bootstrap intervals.

Usage::

    python benchmarks/across_seeds.py outputs/bench/episodes.json [more episodes.json ...] \
        --group ppo-residual=outputs/models/residual-g-s0,outputs/models/residual-g-s1 \
        [--tolerance 2cm/2deg]

Each group is one config trained with several seeds (one policy per seed). For every suite
variant it prints each seed's success rate and their IQM with a 95 % bootstrap interval; then
the IQM over all variants and seeds with a stratified bootstrap (seeds resampled within each
variant), as rliable does (Agarwal et al., NeurIPS 2021).
"""

from __future__ import annotations

import argparse
import json
from collections import defaultdict
from pathlib import Path

import numpy as np

from agents.stats import iqm_interval


def main() -> None:
    """Print the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "episodes", type=Path, nargs="+", help="episodes.json of radial-ibvs benchmark runs"
    )
    parser.add_argument("--group", action="append", required=True, help="NAME=POLICY,POLICY,...")
    parser.add_argument("--tolerance", default="2cm/2deg", help="default: %(default)s")
    args = parser.parse_args()
    rows = [row for path in args.episodes for row in json.loads(path.read_text())]
    for spec in args.group:
        name, _, members = spec.partition("=")
        policies = members.split(",")
        rates: dict[tuple[str, str], dict[str, float]] = defaultdict(dict)
        for policy in policies:
            by_variant: dict[tuple[str, str], list[bool]] = defaultdict(list)
            for row in rows:
                if row["policy"] == policy:
                    ok = row["success_by_tolerance"][args.tolerance]
                    by_variant[row["suite"], row["variant"]].append(bool(ok))
            for key, outcomes in by_variant.items():
                rates[key][policy] = float(np.mean(outcomes))
        print(f"\n{name}: {len(policies)} seeds, success at {args.tolerance}")
        print("| suite | variant | per seed | IQM | 95 % CI |")
        print("|---|---|---|---|---|")
        tasks = []
        for (suite, variant), per in rates.items():
            values = [per[p] for p in policies if p in per]
            cells = " ".join(f"{v:.0%}" for v in values)
            if len(values) < len(policies):  # not every seed ran it: no interval, not in "all"
                cells += f" ({len(values)} of {len(policies)} seeds)"
                print(f"| {suite} | {variant} | {cells} | - | - |")
                continue
            tasks.append(values)
            point, low, high = iqm_interval([values])
            print(f"| {suite} | {variant} | {cells} | {point:.0%} | {low:.0%}-{high:.0%} |")
        if not tasks:
            continue
        point, low, high = iqm_interval(tasks)
        interval = f"{low:.0%}-{high:.0%}"
        print(f"| all | stratified over {len(tasks)} variants | | {point:.0%} | {interval} |")


if __name__ == "__main__":
    main()
