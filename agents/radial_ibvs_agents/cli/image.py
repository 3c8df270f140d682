"""``radial-ibvs image``: a rendered omnidirectional image and its measurement."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from radial_ibvs_agents.cli._options import seed_value

__all__ = ["add_parser", "run"]


def add_parser(sub: Any) -> None:
    """Add the ``image`` sub-command to the sub-parsers ``sub``."""
    parser = sub.add_parser(
        "image",
        help="render an omnidirectional image and draw its measurement (border, beacons)",
        description=(
            "Render what the camera sees from an episode's start pose (clean, and with noise, "
            "blur and under-exposure), fit the mirror border, detect the beacons, and save the "
            "images with the fitted border, the detected centres and the true projections drawn."
        ),
    )
    parser.add_argument("--scenario", default="paper-lab", help="default: %(default)s")
    parser.add_argument(
        "--seed", type=seed_value, default=0, help="episode seed (default: %(default)s)"
    )
    parser.add_argument(
        "--out", type=Path, default=Path("outputs/pixels.png"), help="default: %(default)s"
    )


def run(args: argparse.Namespace) -> int:
    """Run ``radial-ibvs image``; returns the exit code."""
    from radial_ibvs_agents.experiments.pixels import plot_measured

    print(f"saved {plot_measured(args.out, args.scenario, args.seed)}")
    return 0
