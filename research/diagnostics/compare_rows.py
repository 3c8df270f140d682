"""Compare two benchmark outputs row by row, field by field, apart from timing.

Usage: ``python research/diagnostics/compare_rows.py BEFORE/episodes.json AFTER/episodes.json``.
Rows are matched by (policy, suite, variant, seed); every field but the run's timing fields
(``radial_ibvs_agents.rows.RUN_FIELDS``: ``compute_us_per_step``, ``compute_batch``) must be equal,
bit for bit. Prints the number of rows compared and each difference; exits 1 if any.

Used to check that a refactoring changes no episode (issue: the experiment layer's move to
``radial_ibvs_agents.rollouts`` and ``radial_ibvs_agents.rows``).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from radial_ibvs_agents.rows import RUN_FIELDS


def _key(row: dict) -> tuple:
    return (row["policy"], row["suite"], row["variant"], row["seed"])


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("before", type=Path)
    parser.add_argument("after", type=Path)
    parser.add_argument("--ignore", nargs="*", default=list(RUN_FIELDS), help="fields to skip")
    args = parser.parse_args()
    before = {_key(r): r for r in json.loads(args.before.read_text())}
    after = {_key(r): r for r in json.loads(args.after.read_text())}
    differences = 0
    for key in sorted(set(before) ^ set(after), key=str):
        print(f"only in {'before' if key in before else 'after'}: {key}")
        differences += 1
    for key in sorted(set(before) & set(after), key=str):
        a, b = before[key], after[key]
        for field in sorted(set(a) | set(b)):
            if field in args.ignore:
                continue
            if a.get(field, "<missing>") != b.get(field, "<missing>"):
                print(
                    f"{key} {field}: {a.get(field, '<missing>')!r} != {b.get(field, '<missing>')!r}"
                )
                differences += 1
    print(f"{len(set(before) & set(after))} rows compared, {differences} differences")
    return 1 if differences else 0


if __name__ == "__main__":
    sys.exit(main())
