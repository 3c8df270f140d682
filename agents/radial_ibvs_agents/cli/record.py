"""``radial-ibvs record``: a policy's episodes as a ROS 2 bag (MCAP) for Foxglove or ROS 2."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from radial_ibvs_agents.cli._options import add_trust_model_option, policies_help, seed_value

__all__ = ["add_parser", "run"]


def _positive(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not an integer: {text[:40]!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, got {value}")
    return value


def add_parser(sub: Any) -> None:
    """Add the ``record`` sub-command to the sub-parsers ``sub``."""
    parser = sub.add_parser(
        "record",
        help="write a policy's episodes as a ROS 2 bag (MCAP) that Foxglove opens",
        description=(
            "Run a policy's episodes and write them as a ROS 2 bag with MCAP storage (a folder "
            "with metadata.yaml and one .mcap file): images, image points, /cmd_vel, /odom, "
            "/tf, errors and the episode's info, stamped at the control period. With "
            "--env-kwarg measurement=detected the frames the detector read are recorded too. "
            "Needs the [ros] extra. Open the .mcap in Foxglove with the layout "
            "radial_ibvs_agents/bags/foxglove_layout.json (docs: 'On your robot')."
        ),
        epilog=policies_help(),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--policy", required=True, help="policy name or model directory")
    parser.add_argument("--scenario", default="paper-sim", help="default: %(default)s")
    parser.add_argument("--task", type=int, help="task index (default: drawn)")
    parser.add_argument("--episodes", type=_positive, default=1, help="default: %(default)s")
    parser.add_argument(
        "--seed", type=seed_value, default=0, help="episode k gets SEED + k (default: %(default)s)"
    )
    parser.add_argument("--out", type=Path, required=True, help="the bag's folder (new)")
    parser.add_argument(
        "--max-steps", type=_positive, default=600, help="per episode (default: %(default)s)"
    )
    parser.add_argument(
        "--env-kwarg", action="append", default=[], metavar="KEY=VALUE", help="gym.make argument"
    )
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    add_trust_model_option(parser)


def run(args: argparse.Namespace) -> int:
    """Run ``radial-ibvs record``; returns the exit code."""
    import importlib.util
    import sys

    if importlib.util.find_spec("rosbags") is None:
        print(
            "radial-ibvs record: error: ROS 2 bags need the [ros] extra: "
            "pip install 'radial_ibvs_gym[ros]'",
            file=sys.stderr,
        )
        return 2
    from radial_ibvs_agents.bags import FOXGLOVE_LAYOUT
    from radial_ibvs_agents.bags.record import record_episodes
    from radial_ibvs_agents.experiments.evaluate import parse_env_kwargs

    episodes = record_episodes(
        args.policy,
        args.out,
        args.scenario,
        episodes=args.episodes,
        seed=args.seed,
        task=args.task,
        env_kwargs=parse_env_kwargs(args.env_kwarg),
        max_steps=args.max_steps,
        trust_model=args.trust_model,
        progress=not args.no_progress,
    )
    for e in episodes:
        print(
            f"seed {e.seed}: {e.end} after {e.steps} steps, position error "
            f"{100 * e.position_error_m:.1f} cm, heading error {e.heading_error_deg:.1f} deg"
        )
    print(f"saved {args.out} (open {args.out / (args.out.name + '.mcap')} in Foxglove;")
    print(f"layout: {FOXGLOVE_LAYOUT})")
    return 0
