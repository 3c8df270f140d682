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
    return parser


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
    raise AssertionError(f"unhandled command {args.command!r}")  # argparse rejects unknown ones


if __name__ == "__main__":
    sys.exit(main())
