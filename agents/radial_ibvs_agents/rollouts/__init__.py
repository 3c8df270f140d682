"""Rollouts: every episode any command runs goes through here.

- :func:`run_episodes` runs N seeded episodes of a policy, all in one native vector env where
  the episodes allow it (:mod:`radial_ibvs_agents.rollouts.vector`: the same episodes, seed for
  seed), else one by one in a scalar env; ``evaluate``, the benchmark's jobs and the notebooks call
  it;
- :func:`run_episode` steps a policy in a given scalar env for one episode (``render``,
  ``demo``, ``reproduce``: what records frames or sets reset options);
- :func:`env_kwargs_for` merges the ``gym.make`` keywords in one order: the policy's
  ``env_kwargs`` (what its observation needs, and for a learned model the settings it was
  trained with; a named scenario drops those that describe the training world, its
  ``WORLD_KEYS``), then the scenario, then the caller's overrides, which win;
- :func:`make_env` makes the env and checks that a learned model's observation space fits.

Each returns :class:`~radial_ibvs_agents.rollouts.log.EpisodeLog`;
:func:`radial_ibvs_agents.rows.episode_row` makes the table rows of them.

How a policy batches is its own ``batch_mode`` attribute: ``"batch"`` (one ``predict`` for
every robot whose episode goes on), ``"robot"`` (one ``predict`` per robot, e.g. the planner),
or absent (the episodes run one by one in a scalar env).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from typing import Any

from tqdm import tqdm  # text bars: no ipywidgets needed in Jupyter

from radial_ibvs_agents.rollouts.envs import DEFAULT_ENV_ID, env_id_for, env_kwargs_for, make_env
from radial_ibvs_agents.rollouts.log import EpisodeLog
from radial_ibvs_agents.rollouts.scalar import run_episode
from radial_ibvs_agents.rollouts.vector import batchable, run_batch

__all__ = [
    "BATCH",
    "DEFAULT_ENV_ID",
    "EnvMismatchError",
    "EpisodeLog",
    "batch_mode",
    "env_id_for",
    "env_kwargs_for",
    "make_env",
    "run_episode",
    "run_episodes",
]


class EnvMismatchError(ValueError):
    """The env cannot be made for a policy with these keywords, or its observations differ."""


#: the most episodes :func:`run_episodes` steps together (one vector env of this many robots)
BATCH = 100


def batch_mode(policy: Any) -> str | None:
    """How ``policy`` runs in a batch: its ``batch_mode``, ``"batch"`` or ``"robot"``, or None.

    Raises
    ------
    ValueError
        For a ``batch_mode`` that is neither.
    """
    declared = getattr(policy, "batch_mode", None)
    if declared is not None and declared not in ("batch", "robot"):
        raise ValueError(f"batch_mode must be 'batch' or 'robot', got {declared!r}")
    return declared


def run_episodes(
    policy: Any,
    seeds: Sequence[int],
    scenario: str | None = None,
    overrides: Mapping[str, Any] | None = None,
    *,
    tasks: Sequence[int | None] | Callable[[int], Sequence[int | None]] | None = None,
    env_id: str | None = None,
    policy_name: str | None = None,
    batched: bool = True,
    progress: bool = False,
) -> list[EpisodeLog]:
    """Run one episode of ``policy`` per seed; return their logs, in the seeds' order.

    The episodes step together in the native vector env (at most :data:`BATCH` at once) where the
    policy declares a ``batch_mode`` and :func:`~radial_ibvs_agents.rollouts.vector.batchable`
    allows it, else one by one in one scalar env: the same episodes either way, seed for seed
    (:mod:`radial_ibvs_agents.rollouts.vector` says to which bits).

    Parameters
    ----------
    policy
        Anything with SB3's ``predict``.
    seeds
        One reset seed per episode.
    scenario, overrides
        As :func:`env_kwargs_for`.
    tasks
        The reset option ``task`` of each episode (``None``: the env's), ``None`` for all, or
        a function of the scenario's number of tasks that returns them.
    env_id
        As :func:`make_env`.
    policy_name
        Name recorded in the logs (default: the policy's class name).
    batched
        ``False`` runs the episodes one by one even where they could be batched.
    progress
        Show a progress bar (episodes).

    Raises
    ------
    EnvMismatchError
        Where the env cannot be made with the policy's keywords and these, or a learned
        model's observation space differs from the env's (a benchmark reports it skipped).
    ValueError
        For a bad argument.
    """
    kwargs = env_kwargs_for(policy, scenario, overrides)
    try:  # the env the policy needs, its observation checked against the policy's
        env_id = env_id_for(policy, env_id)
        env = make_env(policy, scenario, overrides, env_id=env_id)
    except ValueError as error:
        raise EnvMismatchError(str(error)) from error
    if callable(tasks):
        base: Any = env.unwrapped
        tasks = tasks(int(base.scenario.n_tasks))
    tasks = list(tasks) if tasks is not None else [None] * len(seeds)
    if len(tasks) != len(seeds):
        env.close()
        raise ValueError(f"{len(tasks)} tasks for {len(seeds)} seeds")
    mode = batch_mode(policy) if batched else None
    name = policy_name or type(policy).__name__
    logs: list[EpisodeLog] = []
    with tqdm(total=len(seeds), desc=name, disable=not progress, unit="ep") as bar:
        try:
            if mode is not None and batchable(env_id, kwargs) is None:
                for first in range(0, len(seeds), BATCH):
                    chunk = slice(first, first + BATCH)
                    logs += run_batch(policy, seeds[chunk], env_id, kwargs, tasks=tasks[chunk],
                                      policy_name=name, exact=mode == "batch")  # fmt: skip
                    bar.update(len(seeds[chunk]))
                return logs
            for seed, task in zip(seeds, tasks, strict=True):
                options = None if task is None else {"task": task}
                logs.append(run_episode(policy, env, seed=int(seed), options=options,
                                        policy_name=name))  # fmt: skip
                bar.update(1)
        finally:
            env.close()
    return logs
