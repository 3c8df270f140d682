"""Per-round success of DAgger students, grouped by config: one curve per group, seeds as a band.

Usage::

    python benchmarks/dagger_curves.py --out docs/img/dagger-candidates.png \
        --group "aligning teacher, relative loss=outputs/runs/dagger-set-align-rel-s0" \
        --group "wider drive gate=outputs/runs/dagger-set-gate-s0,outputs/runs/dagger-set-gate-s1"

Each model directory is what ``radial-ibvs distill`` writes (its ``progress.csv``: one row per
round, the success on the config's evaluation rooms). A group of one seed is drawn as its line;
a group of several as the mean across seeds with the band from the lowest to the highest seed,
and each seed's kept round marked. Prints each group's per-round rates.
"""

from __future__ import annotations

import argparse
import csv
import json
from pathlib import Path

import numpy as np

from agents.plotting import save_figure


def read_rounds(directory: Path) -> tuple[np.ndarray, np.ndarray, int | None]:
    """Return ``(env_steps, success_rate, kept round)`` of one DAgger run."""
    with (directory / "progress.csv").open() as file:
        rows = list(csv.DictReader(file))
    if not rows:
        raise ValueError(f"{directory}/progress.csv has no rounds")
    steps = np.array([float(r["env_steps"]) for r in rows])
    success = np.array([float(r["success_rate"]) for r in rows])
    meta = directory / "metadata.json"
    kept = json.loads(meta.read_text()).get("best_round") if meta.is_file() else None
    return steps, success, kept


def main() -> None:
    """Plot and print the groups."""
    import matplotlib.pyplot as plt

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--group", action="append", required=True, help="LABEL=DIR,DIR,...")
    parser.add_argument("--out", type=Path, required=True, help="the figure (.png)")
    args = parser.parse_args()
    fig, ax = plt.subplots(figsize=(7.5, 4.2))
    for k, spec in enumerate(args.group):
        label, _, members = spec.partition("=")
        runs = [read_rounds(Path(d)) for d in members.split(",")]
        n = min(len(r[1]) for r in runs)
        steps = runs[0][0][:n] / 1e6
        table = np.stack([r[1][:n] for r in runs])
        color = f"C{k}"
        mean = table.mean(axis=0)
        name = f"{label} ({len(runs)} seed{'s' if len(runs) > 1 else ''})"
        ax.plot(steps, mean, "o-", color=color, label=name)
        if len(runs) > 1:
            ax.fill_between(steps, table.min(axis=0), table.max(axis=0), color=color, alpha=0.2)
        for _, success, kept in runs:
            if kept is not None and kept < n:
                ax.plot(steps[kept], success[kept], "*", color=color, ms=12, mec="k", mew=0.5)
        cells = "; ".join(" ".join(f"{v:.0%}" for v in row) for row in table)
        print(f"{label}: {cells}")
    ax.set_xlabel("env steps (millions): one point per DAgger round")
    ax.set_ylabel("success, 100 validation rooms")
    ax.set_ylim(0.0, 1.0)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="lower right")
    ax.set_title("DAgger students: success after each round (band: lowest to highest seed)")
    fig.tight_layout()
    save_figure(fig, args.out)
    plt.close(fig)
    print(f"saved {args.out}")


if __name__ == "__main__":
    main()
