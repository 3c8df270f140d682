"""``radial-ibvs sweep``: train one model per seed (locally or on Ray) and summarise the seeds."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from radial_ibvs_agents.cli._options import add_backend_options

__all__ = ["add_parser", "run"]


def add_parser(sub: Any) -> None:
    """Add the ``sweep`` sub-command to the sub-parsers ``sub``."""
    parser = sub.add_parser(
        "sweep",
        help="train one model per seed; IQM and bootstrap interval, curves with seed bands",
        description=(
            "Train the config once per seed (each run as 'radial-ibvs train' writes it, in "
            "OUT/seed-<s>), locally or one Ray task per seed, then write summary.json, "
            "summary.md and learning_curves.png: each seed's success at its last evaluation, their "
            "IQM with a 95 % stratified-bootstrap interval, and the curves. A rerun with the "
            "same --out skips the seeds already trained."
        ),
    )
    parser.add_argument("--config", type=Path, required=True, help="rl-zoo3-format YAML file")
    parser.add_argument("--seeds", type=int, nargs="+", required=True, help="training seeds")
    parser.add_argument("--algo", choices=("ppo", "sac"), default="ppo")
    parser.add_argument("--env-id", help="config section (default: the file's only one)")
    parser.add_argument("--total-timesteps", type=int, help="default: the config's n_timesteps")
    add_backend_options(parser, "seed")
    parser.add_argument(
        "--workers",
        type=int,
        default=1,
        help="seeds trained at once locally (each takes about one core), or the CPUs of a "
        "private Ray instance (default: %(default)s)",
    )
    parser.add_argument("--out", type=Path, default=Path("outputs/sweep"), help="folder")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")


def run(args: argparse.Namespace) -> int:
    """Run ``radial-ibvs sweep``; returns the exit code."""
    from radial_ibvs_agents.experiments.sweep import run_sweep

    run_sweep(
        args.config,
        args.seeds,
        args.out,
        algo=args.algo,
        env_id=args.env_id,
        total_timesteps=args.total_timesteps,
        backend=args.backend,
        address=args.address,
        workers=args.workers,
        progress=not args.no_progress,
        command="radial-ibvs " + " ".join(args.argv),
    )
    print((Path(args.out) / "summary.md").read_text(), end="")
    print(f"saved {args.out}/summary.json, summary.md, learning_curves.png")
    return 0
