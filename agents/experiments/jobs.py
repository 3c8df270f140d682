"""Benchmark jobs: one policy on one suite variant, a chunk of seeded episodes.

A job is a pure function of its fields: the same job gives the same rows in any process, on
any backend.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from agents import make_policy
from agents.experiments.suites import Variant
from agents.runner import make_env, run_episode

__all__ = ["CHUNK", "Job", "JobResult", "init_worker", "run_job"]


@dataclass(frozen=True)
class Job:
    """One policy on one suite variant: episodes (seeds) ``first`` to ``first + episodes - 1``."""

    policy: str
    variant: Variant
    episodes: int
    first: int = 0
    #: load a model directory that holds only a pickled ``model.zip`` (``--trust-model``)
    trust_model: bool = False


#: episodes per job: long variants are split so that the workers share them
CHUNK = 20


@dataclass
class JobResult:
    """Rows of a job, the paths of its first episodes, or why it was skipped."""

    job: Job
    rows: list[dict[str, Any]]
    paths: list[tuple[int | None, np.ndarray]]
    skipped: str | None = None


def init_worker() -> None:
    """One torch thread per worker process: the workers already share the cores."""
    import torch

    torch.set_num_threads(1)


def run_job(job: Job) -> JobResult:
    """Run a job (in a worker process)."""
    policy = make_policy(job.policy, trust_pickle=job.trust_model)
    # the suite chooses the task per episode: a learned model's training task is dropped
    overrides = {**job.variant.overrides, "task": None}
    try:
        env = make_env(policy, job.variant.scenario, overrides)
    except ValueError as error:  # a learned model whose observations do not fit
        return JobResult(job, [], [], skipped=str(error))
    base: Any = env.unwrapped
    n_tasks = base.scenario.n_tasks
    rows, paths = [], []
    for k in range(job.first, job.first + job.episodes):
        options = {"task": k % n_tasks} if job.variant.cycle_tasks else None
        seed = job.variant.seed_offset + k
        log = run_episode(policy, env, seed=seed, options=options, policy_name=job.policy)
        row = log.row()
        row.update(
            suite=job.variant.suite,
            variant=job.variant.label,
            start_pose=[float(v) for v in log.poses[0]],
            goal_pose=[float(v) for v in log.info["goal_pose"]],
        )
        rows.append(row)
        if k < n_tasks or (not job.variant.cycle_tasks and k < 8):
            paths.append((log.task, log.poses[:, :2]))
    env.close()
    return JobResult(job, rows, paths)
