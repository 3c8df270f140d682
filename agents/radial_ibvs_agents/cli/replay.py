"""``radial-ibvs replay``: a recording's frames through the pixel pipeline and a policy."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

import numpy as np

from radial_ibvs_agents.cli._options import add_trust_model_option, policies_help

__all__ = ["add_parser", "run"]


def _pose(text: str) -> np.ndarray:
    parts = text.split(",")
    try:
        values = np.array([float(p) for p in parts])
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"expected X,Y,YAW (m, m, rad), got {text[:60]!r}"
        ) from None
    if values.shape != (3,) or not np.isfinite(values).all():
        raise argparse.ArgumentTypeError(f"expected X,Y,YAW (m, m, rad), got {text[:60]!r}")
    return values


def add_parser(sub: Any) -> None:
    """Add the ``replay`` sub-command to the sub-parsers ``sub``."""
    parser = sub.add_parser(
        "replay",
        help="run a recording's frames through the pixel pipeline and a policy; write commands",
        description=(
            "Read a ROS 2 bag (MCAP) of omnidirectional frames, run the pixel pipeline "
            "(border fit on the goal image, detection, tracking, matching) and an image-only "
            "policy on each frame, with the frames' own time stamps, and write the command "
            "each frame would send (/cmd_vel) beside the detections, as a bag and a CSV "
            "(OUT/commands.csv). The landmarks are labelled from a map and the poses of the "
            "goal image and the first frame: by default the bag's /landmarks, /tf (goal) and "
            "/odom, as radial-ibvs record writes them. Needs the [ros] extra."
        ),
        epilog=policies_help(),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("bag", type=Path, help="a rosbag2 folder with one .mcap, or the .mcap")
    parser.add_argument("--policy", required=True, help="an image-only policy (name or model)")
    parser.add_argument(
        "--scenario", default="paper-lab", help="the camera and beacons (default: %(default)s)"
    )
    parser.add_argument("--out", type=Path, required=True, help="the output bag's folder (new)")
    parser.add_argument("--image-topic", default="/camera/image", help="default: %(default)s")
    parser.add_argument(
        "--goal-image-topic", default="/camera/goal_image", help="default: %(default)s"
    )
    parser.add_argument(
        "--episode", type=int, default=0, help="which goal image of the bag (default: %(default)s)"
    )
    goal = parser.add_mutually_exclusive_group()
    goal.add_argument(
        "--goal-image", type=Path, help="the goal image: a grey PNG or a .npy (H, W) uint8 file"
    )
    goal.add_argument(
        "--goal-at",
        type=float,
        metavar="SECONDS",
        help="the goal image: the frame nearest this time after the image topic's first",
    )
    parser.add_argument(
        "--labels",
        type=Path,
        help="YAML: the landmarks' pixels in the goal image and first frame, and the goal "
        "depths (instead of a map and poses; docs: On your robot)",
    )
    parser.add_argument(
        "--motion",
        choices=("policy", "recorded"),
        default="policy",
        help="what pbvs-ekf and ekf-planner predict the motion from: their own commands, or "
        "the commands the robot executed (--command-topic) (default: %(default)s)",
    )
    parser.add_argument(
        "--camera",
        type=Path,
        help="YAML: the scenario's camera section (mirror, non_central_offset, imperfections: "
        "the principal point's offset and the focal ratio's error against the nominal ones)",
    )
    parser.add_argument("--command-topic", default="/cmd_vel", help="default: %(default)s")
    parser.add_argument(
        "--start", type=_pose, help="the first frame's pose X,Y,YAW (default: /odom)"
    )
    parser.add_argument("--goal", type=_pose, help="the goal image's pose X,Y,YAW (default: /tf)")
    parser.add_argument(
        "--env-kwarg", action="append", default=[], metavar="KEY=VALUE", help="gym.make argument"
    )
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    add_trust_model_option(parser)


def run(args: argparse.Namespace) -> int:
    """Run ``radial-ibvs replay``; returns the exit code."""
    import importlib.util
    import sys

    if importlib.util.find_spec("rosbags") is None or importlib.util.find_spec("mcap") is None:
        print(
            "radial-ibvs replay: error: ROS 2 bags need the [ros] extra: "
            "pip install 'radial_ibvs_gym[ros]'",
            file=sys.stderr,
        )
        return 2
    from radial_ibvs_agents.bags.replay import replay_bag
    from radial_ibvs_agents.experiments.evaluate import parse_env_kwargs

    env_kwargs = parse_env_kwargs(args.env_kwarg)
    if args.camera is not None:
        from radial_ibvs_gym.config.yaml_files import read_yaml

        if "camera" in env_kwargs:
            raise ValueError("give the camera with --camera or --env-kwarg camera=..., not both")
        env_kwargs["camera"] = read_yaml(args.camera)
    result = replay_bag(
        args.bag,
        args.policy,
        args.out,
        args.scenario,
        env_kwargs=env_kwargs,
        image_topic=args.image_topic,
        goal_image_topic=args.goal_image_topic,
        episode=args.episode,
        start=args.start,
        goal=args.goal,
        goal_image=args.goal_image,
        goal_at=args.goal_at,
        labels=args.labels,
        motion=args.motion,
        command_topic=args.command_topic,
        trust_model=args.trust_model,
        progress=not args.no_progress,
    )
    frames = len(result.stamps_ns)
    tracked = result.visible.sum(axis=1)
    print(
        f"{frames} frames, {result.dropped} dropped; landmarks tracked per frame: median "
        f"{int(np.median(tracked))}, fewest {int(tracked.min())}"
    )
    print(f"saved {args.out} (/cmd_vel, /image_points, /detection) and {args.out / 'commands.csv'}")
    return 0
