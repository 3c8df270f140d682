"""``radial-ibvs collect``: a policy's episodes as a local Minari dataset."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from radial_ibvs_agents.cli._options import add_trust_model_option, policies_help, seed_value

__all__ = ["add_parser", "run"]


def add_parser(sub: Any) -> None:
    """Add the ``collect`` sub-command to the sub-parsers ``sub``."""
    parser = sub.add_parser(
        "collect",
        help="record a policy's episodes as a Minari dataset (offline RL, distillation)",
        description=(
            "Run a policy (e.g. the planner) for N episodes seeded S, S+1, ... and write them "
            "as a Minari dataset (Farama's offline-RL format, HDF5) in OUT/<dataset id>, "
            "locally: nothing is uploaded. The observations are the env's whole Dict "
            "observation: the learned models' features observation (16 landmark slots, goal "
            "depths) plus what the policy needs. Needs the [datasets] extra."
        ),
        epilog=policies_help(),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--policy", required=True, help="policy name or model directory")
    parser.add_argument("--scenario", default="random", help="default: %(default)s")
    parser.add_argument("--episodes", type=int, default=100, help="default: %(default)s")
    parser.add_argument(
        "--seed", type=seed_value, default=0, help="first seed (default: %(default)s)"
    )
    parser.add_argument("--out", type=Path, default=Path("outputs/datasets"), help="datasets dir")
    parser.add_argument("--dataset-id", help="Minari id (default: radial-ibvs/POLICY_SCENARIO-v0)")
    parser.add_argument(
        "--env-kwarg", action="append", default=[], metavar="KEY=VALUE", help="override"
    )
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    add_trust_model_option(parser)


def run(args: argparse.Namespace) -> int:
    """Run ``radial-ibvs collect``; returns the exit code."""
    from radial_ibvs_agents.experiments.collect import collect
    from radial_ibvs_agents.experiments.evaluate import parse_env_kwargs
    from radial_ibvs_agents.learned.dagger.datasets import load_collected

    path = collect(
        args.policy,
        args.scenario,
        args.episodes,
        args.out,
        seed=args.seed,
        env_kwargs=parse_env_kwargs(args.env_kwarg),
        dataset_id=args.dataset_id,
        trust_model=args.trust_model,
        progress=not args.no_progress,
    )
    dataset = load_collected(path)
    print(f"saved {path}: {dataset.total_episodes} episodes, {dataset.total_steps} steps")
    return 0
