"""``radial-ibvs distill``: teach an image-only student from a privileged teacher (DAgger)."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from radial_ibvs_agents.cli._options import seed_value

__all__ = ["add_parser", "run"]


def add_parser(sub: Any) -> None:
    """Add the ``distill`` sub-command to the sub-parsers ``sub``."""
    parser = sub.add_parser(
        "distill",
        help="DAgger: distil the planner into an image-only student",
        description=(
            "Run DAgger with the settings of a YAML file (configs/agents/dagger_student.yaml, "
            "the shipped student's; the wheel carries it as "
            "radial_ibvs_gym/_configs/agents/dagger_student.yaml): "
            "the teacher (the planner, which sees the poses and the map) labels the states the "
            "student visits; the student (an SB3 PPO policy on the features observation) is "
            "fitted to the labels after each round and evaluated on held-out seeds. Writes a "
            "model directory that `radial-ibvs evaluate --policy DIR` and "
            "radial_ibvs_agents.load(DIR) "
            "read, progress.csv and learning_curve.png, and the student after each round in "
            "DIR/rounds/."
        ),
    )
    parser.add_argument("--config", type=Path, required=True, help="DAgger YAML file")
    parser.add_argument("--seed", type=seed_value, default=0, help="default: %(default)s")
    parser.add_argument("--out", type=Path, default=Path("outputs/distill"), help="model directory")
    parser.add_argument("--rounds", type=int, help="default: the config's rounds")
    parser.add_argument(
        "--env-kwarg", action="append", default=[], metavar="KEY=VALUE", help="override"
    )
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")


def run(args: argparse.Namespace) -> int:
    """Run ``radial-ibvs distill``; returns the exit code."""
    import dataclasses

    from radial_ibvs_agents.experiments.evaluate import parse_env_kwargs
    from radial_ibvs_agents.learned.dagger.distill import dagger, load_dagger_config

    config = load_dagger_config(args.config)
    overrides = parse_env_kwargs(args.env_kwarg)
    if overrides:
        config = dataclasses.replace(config, env_kwargs={**config.env_kwargs, **overrides})
    if args.rounds is not None:
        if args.rounds < 1:
            raise ValueError(f"--rounds must be >= 1, got {args.rounds}")
        config = dataclasses.replace(config, rounds=args.rounds)
    out = dagger(
        config,
        args.out,
        seed=args.seed,
        progress=not args.no_progress,
        command="radial-ibvs " + " ".join(args.argv),
    )
    print(f"saved {out}")
    return 0
