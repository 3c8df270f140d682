"""``radial-ibvs evaluate``: run one policy on a scenario for a number of seeded episodes."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from radial_ibvs_agents import make_policy
from radial_ibvs_agents.rollouts import run_episodes
from radial_ibvs_agents.rollouts.log import EpisodeLog
from radial_ibvs_gym.config import read_yaml, short

__all__ = ["evaluate", "parse_env_kwargs"]


def parse_env_kwargs(pairs: Sequence[str]) -> dict[str, Any]:
    """``KEY=VALUE`` strings to keyword arguments; values are read as YAML (numbers, lists...).

    Raises
    ------
    ValueError
        For an item without ``=`` or a value that is not valid YAML.
    """
    out: dict[str, Any] = {}
    for pair in pairs:
        key, sep, value = pair.partition("=")
        if not sep or not key:
            raise ValueError(f"--env-kwarg expects KEY=VALUE, got {pair!r}")
        out[key] = read_yaml(value, f"--env-kwarg {short(key)}")
    return out


def evaluate(
    policy_name: str,
    scenario: str = "paper-sim",
    *,
    task: int | None = None,
    episodes: int = 10,
    seed: int = 0,
    env_kwargs: Mapping[str, Any] | None = None,
    env_id: str | None = None,
    suite: str | None = None,
    progress: bool = True,
    trust_model: bool = False,
) -> list[EpisodeLog]:
    """Run ``episodes`` episodes seeded ``seed, seed + 1, ...`` (``radial_ibvs_agents.rollouts``).

    Through :func:`radial_ibvs_agents.rollouts.run_episodes`: batched in the native vector env where
    the policy and the env allow it (the same episodes as one at a time), else one at a time in a
    scalar env.

    ``trust_model`` allows a model directory that holds only a pickled stable-baselines3
    ``model.zip`` (:func:`radial_ibvs_agents.learned.load`'s ``trust_pickle``).

    Raises
    ------
    ValueError
        For an unknown policy, scenario or argument, or a learned model whose observation
        space differs from the env's.
    """
    if episodes <= 0:
        raise ValueError(f"episodes must be positive, got {episodes!r}")
    policy = make_policy(policy_name, trust_pickle=trust_model)
    overrides = {**(env_kwargs or {}), **({"task": task} if task is not None else {})}
    seeds = list(range(seed, seed + episodes))
    logs = run_episodes(policy, seeds, scenario, overrides, env_id=env_id,
                        policy_name=policy_name, progress=progress)  # fmt: skip
    if suite is not None:
        for log in logs:
            log.extra["suite"] = suite
    return logs
