"""The ``radial-ibvs`` command line.

Sub-commands land with the issues that build them; ``demo`` is the main job of the quick start.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path

__all__ = ["build_parser", "main"]


def build_parser() -> argparse.ArgumentParser:
    """Return the argument parser of ``radial-ibvs`` (one sub-parser per command)."""
    parser = argparse.ArgumentParser(
        prog="radial-ibvs",
        description=(
            "Visual servoing of mobile robots with (non-)central catadioptric cameras "
            "(Aliakbarpour, Tahri, Araujo, RAS 2014)."
        ),
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)

    demo = sub.add_parser(
        "demo",
        help="project the paper's scene through mirrors A and B, drive the robot; save figures",
        description=(
            "Project the 8 points of the paper's eq. (39) through its two hyperbolic mirrors "
            "(A and B) from the start pose and a goal pose of a parking task, check the radial "
            "invariance (eq. 7 on the exact pixels equals eq. 9), and save a figure; then drive "
            "the robot of RadialIBVS/Parking-v0 (paper-sim) with random actions and save a "
            "rendered frame next to it (<out>-episode.png)."
        ),
    )
    demo.add_argument(
        "--out",
        type=Path,
        default=Path("outputs/demo.png"),
        help="where to save the figure (PNG, PDF or SVG; default: %(default)s)",
    )
    demo.add_argument(
        "--task",
        type=int,
        choices=(0, 1, 2, 3),
        default=1,
        help="parking task whose goal pose is shown (goal yaw 0/90/180/270 deg; "
        "default: %(default)s)",
    )
    demo.add_argument(
        "--non-central-offset",
        type=float,
        default=0.01,
        metavar="METRES",
        help="on-axis shift of the pinhole from the mirror focus, metres (0 = central; "
        "default: %(default)s)",
    )
    reproduce = sub.add_parser(
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
    reproduce.add_argument("scenario", nargs="?", default="paper-sim", help="default: %(default)s")
    reproduce.add_argument(
        "--physics",
        nargs="+",
        choices=("kinematic", "pymunk"),
        default=["kinematic", "pymunk"],
        help="backends to run (default: both)",
    )
    reproduce.add_argument(
        "--out", type=Path, default=Path("outputs/reproduce"), help="output folder"
    )
    reproduce.add_argument("--json", type=Path, help="also write the per-episode rows here")
    reproduce.add_argument("--tasks", type=int, nargs="+", help="task indices (default: all)")
    reproduce.add_argument(
        "--lam", type=float, default=0.5, help="IBVS gain lambda, 1/s (default: %(default)s)"
    )
    reproduce.add_argument(
        "--control-dt", type=float, default=0.1, help="control period, s (default: %(default)s)"
    )
    reproduce.add_argument(
        "--max-steps", type=int, default=1000, help="step budget per episode (default: %(default)s)"
    )
    reproduce.add_argument("--no-robustness", action="store_true", help="skip the robustness cases")
    reproduce.add_argument(
        "--no-figures", action="store_true", help="write the table and data only"
    )
    return parser


def _reproduce(args: argparse.Namespace) -> int:
    from radial_ibvs_gym.experiments import (
        CASES,
        ROBUSTNESS_CASES,
        reproduce,
        summary_table,
        write_atomic,
        write_json,
        write_trajectories_csv,
    )

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
    out: Path = args.out
    written = [
        write_atomic(out / "table.md", table),
        write_trajectories_csv(logs, out / "trajectories.csv"),
        write_json(logs, out / "results.json"),
    ]
    if args.json is not None:
        written.append(write_json(logs, args.json))
    if not args.no_figures:
        from radial_ibvs_gym.experiments.figures import plot_paths, plot_servoing

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


def main(argv: Sequence[str] | None = None) -> int:
    """Run ``radial-ibvs``; returns the process exit code."""
    args = build_parser().parse_args(argv)
    if args.command == "demo":
        from radial_ibvs_gym.demo import run_demo, run_episode_demo

        path = run_demo(out=args.out, task=args.task, non_central_offset=args.non_central_offset)
        print(f"saved {path}")
        episode = args.out.with_name(f"{args.out.stem}-episode.png")
        print(f"saved {run_episode_demo(out=episode, task=args.task)}")
        return 0
    if args.command == "reproduce":
        try:
            return _reproduce(args)
        except ValueError as error:  # bad scenario, task or value: a message, not a traceback
            print(f"radial-ibvs reproduce: error: {error}", file=sys.stderr)
            return 2
    raise AssertionError(f"unhandled command {args.command!r}")  # argparse rejects unknown ones


if __name__ == "__main__":
    sys.exit(main())
