"""``radial-ibvs reproduce``: the paper's Section 4.1 (table, trajectories, rows, figures)."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

__all__ = ["add_parser", "run"]


def add_parser(sub: Any) -> None:
    """Add the ``reproduce`` sub-command to the sub-parsers ``sub``."""
    parser = sub.add_parser(
        "reproduce",
        help="reproduce the paper's Section 4.1: table, trajectories.csv, figures",
        description=(
            "Run the four parking tasks of a scenario with (a) the paper's IBVS, (b) the pose "
            "oracle (the same smooth control law fed the true poses) and (c) the IBVS with goal "
            "depths scaled by 1.3, on each physics backend, plus the robustness cases (goal "
            "image through mirror B, 0.5 px pixel noise, a 3 px principal-point error). "
            "Success is the paper's accuracy, 1 cm and 0.5 deg. Writes into --out: table.md, "
            "trajectories.csv (policy, task, physics, t, x, y, yaw), fig3-paths-<physics>.png "
            "(IBVS vs oracle), fig4-depth-scale-<physics>.png (d* vs 1.3 d*), "
            "fig6-8-servoing-task<k>.png (image, feature and alpha_m errors, velocities) and "
            "results.json (one row per episode)."
        ),
    )
    parser.add_argument("scenario", nargs="?", default="paper-sim", help="default: %(default)s")
    parser.add_argument(
        "--physics",
        nargs="+",
        choices=("kinematic", "pymunk"),
        default=["kinematic", "pymunk"],
        help="backends to run (default: both)",
    )
    parser.add_argument(
        "--out",
        type=Path,
        help="output folder (default: outputs/reproduce/SCENARIO, one folder per scenario)",
    )
    parser.add_argument("--json", type=Path, help="also write the per-episode rows here")
    parser.add_argument("--tasks", type=int, nargs="+", help="task indices (default: all)")
    parser.add_argument(
        "--lam", type=float, default=0.5, help="IBVS gain lambda, 1/s (default: %(default)s)"
    )
    parser.add_argument(
        "--control-dt", type=float, default=0.1, help="control period, s (default: %(default)s)"
    )
    parser.add_argument(
        "--max-steps", type=int, default=1000, help="step budget per episode (default: %(default)s)"
    )
    parser.add_argument("--no-robustness", action="store_true", help="skip the robustness cases")
    parser.add_argument("--no-figures", action="store_true", help="write the table and data only")


def run(args: argparse.Namespace) -> int:
    """Run ``radial-ibvs reproduce``; returns the exit code."""
    from radial_ibvs_agents.experiments import (
        CASES,
        ROBUSTNESS_CASES,
        reproduce,
        summary_table,
        write_json,
        write_trajectories_csv,
    )
    from radial_ibvs_agents.io import write_atomic

    cases = CASES if args.no_robustness else CASES + ROBUSTNESS_CASES
    logs = reproduce(
        args.scenario,
        physics=args.physics,
        tasks=args.tasks,
        cases=cases,
        control_dt=args.control_dt,
        lam=args.lam,
        max_steps=args.max_steps,
    )
    table = summary_table(logs)
    print(table)
    name = Path(str(args.scenario)).stem  # a YAML path: its file name
    out: Path = args.out if args.out is not None else Path("outputs/reproduce") / name
    written = [
        write_atomic(out / "table.md", table),
        write_trajectories_csv(logs, out / "trajectories.csv"),
        write_json(logs, out / "results.json"),
    ]
    if args.json is not None:
        written.append(write_json(logs, args.json))
    if not args.no_figures:
        from radial_ibvs_agents.experiments.figures import plot_paths, plot_servoing

        for backend in args.physics:
            mine = [log for log in logs if log.physics == backend]
            written.append(
                plot_paths(
                    mine,
                    ("ibvs", "oracle"),
                    out / f"fig3-paths-{backend}.png",
                    f"IBVS vs the pose oracle (real 3D parameters), {backend}",
                )
            )
            written.append(
                plot_paths(
                    mine,
                    ("ibvs", "ibvs-d1.3"),
                    out / f"fig4-depth-scale-{backend}.png",
                    f"IBVS with d* and with 1.3 d*, {backend}",
                )
            )
        first = args.physics[0]
        for log in logs:
            if log.physics == first and log.policy in ("ibvs", "ibvs-noise-0.5px"):
                suffix = "" if log.policy == "ibvs" else f"-{log.policy}"
                name = f"fig6-8-servoing-task{log.task}{suffix}.png"
                written.append(plot_servoing(log, out / name, lam=args.lam))
    for path in written:
        print(f"saved {path}")
    return 0
