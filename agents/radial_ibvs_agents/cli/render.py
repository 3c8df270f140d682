"""``radial-ibvs render``: a GIF or MP4 of a policy parking."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from radial_ibvs_agents.cli._options import add_trust_model_option, policies_help, seed_value

__all__ = ["add_parser", "run"]


def add_parser(sub: Any) -> None:
    """Add the ``render`` sub-command to the sub-parsers ``sub``."""
    parser = sub.add_parser(
        "render",
        help="save a video (GIF, or MP4 with ffmpeg) of a policy parking",
        description="Run one episode of a policy with rgb_array rendering and save it.",
        epilog=policies_help(),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--policy", required=True, help="policy name or model directory")
    parser.add_argument("--scenario", default="paper-sim", help="default: %(default)s")
    parser.add_argument("--task", type=int, help="task index (default: drawn)")
    parser.add_argument("--seed", type=seed_value, default=0, help="default: %(default)s")
    parser.add_argument("--out", type=Path, required=True, help="FILE.gif or FILE.mp4")
    parser.add_argument("--fps", type=int, default=10, help="default: %(default)s")
    parser.add_argument("--max-steps", type=int, default=600, help="default: %(default)s")
    parser.add_argument(
        "--env-kwarg", action="append", default=[], metavar="KEY=VALUE", help="gym.make argument"
    )
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    add_trust_model_option(parser)


def run(args: argparse.Namespace) -> int:
    """Run ``radial-ibvs render``; returns the exit code."""
    from radial_ibvs_agents.experiments.evaluate import parse_env_kwargs
    from radial_ibvs_agents.experiments.video import render_episode

    path, info = render_episode(
        args.policy,
        args.out,
        args.scenario,
        task=args.task,
        seed=args.seed,
        env_kwargs=parse_env_kwargs(args.env_kwarg),
        fps=args.fps,
        max_steps=args.max_steps,
        trust_model=args.trust_model,
        progress=not args.no_progress,
    )
    outcome = "parked" if info.get("is_success") else "did not park"
    print(
        f"{args.policy} {outcome}: position error {100 * info['position_error_m']:.1f} cm, "
        f"heading error {info['heading_error_deg']:.1f} deg"
    )
    print(f"saved {path}")
    return 0
