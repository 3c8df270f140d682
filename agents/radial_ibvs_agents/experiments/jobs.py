"""Benchmark jobs: one policy on one suite variant, a chunk of seeded episodes.

A job is a pure function of its fields: the same job gives the same rows in any process, on
any backend.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from radial_ibvs_agents import make_policy
from radial_ibvs_agents.experiments.suites import Variant
from radial_ibvs_agents.rollouts import EnvMismatchError, run_episodes
from radial_ibvs_agents.rows import JUDGING, episode_row

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


#: episodes per job: long variants are split so that the workers share them. A job's episodes
#: step together in one vector env (:mod:`radial_ibvs_agents.rollouts.vector`), so a larger chunk
#: amortises each batched call over more robots: 100 covers most variants in one job
CHUNK = 100


@dataclass
class JobResult:
    """Rows of a job, the paths of its first episodes, or why it was skipped."""

    job: Job
    rows: list[dict[str, Any]]
    paths: list[tuple[int | None, np.ndarray]]
    skipped: str | None = None
    #: seconds the job took in its worker (``None``: loaded from a saved chunk, not run now)
    wall_s: float | None = None
    #: chunks of this result loaded from saved chunks (a resumed run), not timed now
    resumed: int = 0


def init_worker() -> None:
    """One thread per worker process for torch and OpenCV: the workers already share the cores.

    OpenCV's own threads (the detected-points suites' connected components, blur and
    dilations) would otherwise compete with the other workers for the same cores (the rows
    are the same either way). ``radial-ibvs benchmark`` also starts its workers with
    ``OMP_NUM_THREADS=1`` unless it is set, for numpy's BLAS.
    """
    import cv2
    import torch

    torch.set_num_threads(1)
    cv2.setNumThreads(1)


def run_job(job: Job) -> JobResult:
    """Run a job (in a worker process): its episodes through ``rollouts.run_episodes``.

    Batched or not, a job's rows are the same through an ideal camera (timing apart); through an
    imperfect one, to the last digits (:mod:`radial_ibvs_agents.rollouts.vector` says how far). A
    policy whose observations do not fit the variant's env is skipped, with the reason.
    """
    start = time.perf_counter()
    policy = make_policy(job.policy, trust_pickle=job.trust_model)
    # the suite chooses the task per episode (a learned model's training task is dropped) and
    # judges every policy alike (a model's training env may have asked a hold)
    overrides = {**JUDGING, **job.variant.overrides, "task": None}
    ks = list(range(job.first, job.first + job.episodes))
    seeds = [job.variant.seed_offset + k for k in ks]
    scenario_tasks: list[int] = []

    def tasks(n_tasks: int) -> list[int | None]:  # episode k: task k % n (the paper's four)
        scenario_tasks.append(n_tasks)
        return [k % n_tasks if job.variant.cycle_tasks else None for k in ks]

    try:
        logs = run_episodes(policy, seeds, job.variant.scenario, overrides, tasks=tasks,
                            policy_name=job.policy)  # fmt: skip
    except EnvMismatchError as error:
        return JobResult(job, [], [], skipped=str(error), wall_s=time.perf_counter() - start)
    rows, paths = [], []
    for k, log in zip(ks, logs, strict=True):
        rows.append(episode_row(log, job.variant))
        if k < scenario_tasks[0] or (not job.variant.cycle_tasks and k < 8):
            paths.append((log.task, log.poses[:, :2]))
    return JobResult(job, rows, paths, wall_s=time.perf_counter() - start)
