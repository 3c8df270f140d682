"""``radial-ibvs demo``: the quick start's main job (the scene through two mirrors, a parking)."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

__all__ = ["add_parser", "run"]


def add_parser(sub: Any) -> None:
    """Add the ``demo`` sub-command to the sub-parsers ``sub``."""
    parser = sub.add_parser(
        "demo",
        help="project the paper's scene through mirrors A and B, drive the robot; save figures",
        description=(
            "Project the 8 points of the paper's eq. (39) through its two hyperbolic mirrors "
            "(A and B) from the start pose and a goal pose of a parking task, check the radial "
            "invariance (eq. 7 on the exact pixels equals eq. 9), and save a figure; then drive "
            "the robot of RadialIBVS/Parking-v0 (paper-sim) to the goal with the paper's IBVS "
            "(from the image points only) and save a "
            "rendered frame next to it (<out>-episode.png)."
        ),
    )
    parser.add_argument(
        "--out",
        type=Path,
        default=Path("outputs/demo.png"),
        help="where to save the figure (PNG, PDF or SVG; default: %(default)s)",
    )
    parser.add_argument(
        "--task",
        type=int,
        choices=(0, 1, 2, 3),
        default=1,
        help="parking task whose goal pose is shown (goal yaw 0/90/180/270 deg; "
        "default: %(default)s)",
    )
    parser.add_argument(
        "--non-central-offset",
        type=float,
        default=0.01,
        metavar="METRES",
        help="on-axis shift of the pinhole from the mirror focus, metres (0 = central; "
        "default: %(default)s)",
    )


def run(args: argparse.Namespace) -> int:
    """Run ``radial-ibvs demo``; returns the exit code."""
    from radial_ibvs_agents.experiments.demo import run_demo, run_episode_demo

    path = run_demo(out=args.out, task=args.task, non_central_offset=args.non_central_offset)
    print(f"saved {path}")
    episode = args.out.with_name(f"{args.out.stem}-episode.png")
    print(f"saved {run_episode_demo(out=episode, task=args.task)}")
    return 0
