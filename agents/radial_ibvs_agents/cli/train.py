"""``radial-ibvs train``: train a stable-baselines3 agent from an rl-zoo3-format config."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from radial_ibvs_agents.cli._options import seed_value

__all__ = ["add_parser", "run"]


def add_parser(sub: Any) -> None:
    """Add the ``train`` sub-command to the sub-parsers ``sub``."""
    parser = sub.add_parser(
        "train",
        help="train a stable-baselines3 agent from an rl-zoo3-style config",
        description=(
            "Train PPO (or SAC) with the hyper-parameters of an rl-zoo3-format YAML file "
            "(configs/agents/ppo_parking.yaml): vectorised envs, observation normalisation, "
            "evaluation on held-out seeds with best-model checkpointing, checkpoints, CSV "
            "(and TensorBoard) logs, a progress bar. Writes a model directory that "
            "`radial-ibvs evaluate --policy DIR` and radial_ibvs_agents.load(DIR) read."
        ),
    )
    parser.add_argument(
        "--algo", choices=("ppo", "sac", "tqc"), default="ppo", help="tqc needs sb3-contrib"
    )
    parser.add_argument("--config", type=Path, required=True, help="rl-zoo3-format YAML file")
    parser.add_argument("--env-id", help="config section (default: the file's only one)")
    parser.add_argument("--seed", type=seed_value, default=0, help="default: %(default)s")
    parser.add_argument("--total-timesteps", type=int, help="default: the config's n_timesteps")
    parser.add_argument("--out", type=Path, default=Path("outputs/train"), help="model directory")
    parser.add_argument(
        "--resume",
        type=Path,
        help="model directory, or checkpoints/rl_model_N_steps.zip, to continue training from: "
        "its weights and optimizer state (tensors only) and normalization.npz; no pickle is read",
    )
    parser.add_argument(
        "--init-from",
        type=Path,
        help="model directory to fine-tune (e.g. a DAgger student from radial-ibvs distill): "
        "its architecture, weights, history and normalisation; PPO only",
    )
    parser.add_argument(
        "--env-kwarg", action="append", default=[], metavar="KEY=VALUE", help="override"
    )
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")


def run(args: argparse.Namespace) -> int:
    """Run ``radial-ibvs train``; returns the exit code."""
    import dataclasses

    from radial_ibvs_agents.experiments.evaluate import parse_env_kwargs
    from radial_ibvs_agents.learned.training.train import train
    from radial_ibvs_agents.learned.training.zoo_config import load_train_config

    config = load_train_config(args.config, args.env_id)
    overrides = parse_env_kwargs(args.env_kwarg)
    if overrides:
        config = dataclasses.replace(config, env_kwargs={**config.env_kwargs, **overrides})
    steps = config.n_timesteps if args.total_timesteps is None else args.total_timesteps
    print(  # at once: a run shows no bar when its output is not a terminal
        f"training {args.algo} on {config.env_id} for {int(steps):,} steps with "
        f"{config.n_envs} envs into {args.out} (evaluations every {config.eval_freq:,} steps; "
        f"the log: {args.out}/logs/progress.csv)",
        flush=True,
    )
    out = train(
        config,
        args.out,
        algo=args.algo,
        seed=args.seed,
        total_timesteps=args.total_timesteps,
        resume=args.resume,
        init_from=args.init_from,
        progress=not args.no_progress,
        command="radial-ibvs " + " ".join(args.argv),
    )
    print(f"saved {out}")
    return 0
