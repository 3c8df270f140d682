"""Benchmark results persisted per chunk, so an interrupted run resumes where it stopped.

Each finished job (one policy, one suite variant, a chunk of seeded episodes) is written at
once to ``<out>/chunks/<name>.json`` (atomically: a file is complete or absent). A rerun with
the same ``--out`` loads the chunks already there instead of running them again. A chunk's
file name holds a digest of everything that defines its rows (policy, and for a learned model
the bytes of its ``model.zip``; suite variant, its ``gym.make`` overrides, scenario, seeds,
episodes), so a changed job, or a retrained model, is never mistaken for a done one.
"""

from __future__ import annotations

import functools
import hashlib
import json
import re
from pathlib import Path
from typing import Any

import numpy as np

from agents.experiments.jobs import Job, JobResult
from agents.io import write_json

__all__ = ["ChunkStore", "job_key"]


def job_key(job: Job) -> str:
    """Return a file name for the job: readable parts and a digest of its defining fields."""
    variant = job.variant
    fields = {
        "policy": job.policy,
        "suite": variant.suite,
        "label": variant.label,
        "scenario": variant.scenario,
        "overrides": variant.overrides,
        "cycle_tasks": variant.cycle_tasks,
        "seed_offset": variant.seed_offset,
        "first": job.first,
        "episodes": job.episodes,
        "model": _model_digest(job.policy),
    }
    text = json.dumps(fields, sort_keys=True, default=repr)
    digest = hashlib.sha256(text.encode()).hexdigest()[:12]
    readable = re.sub(r"[^A-Za-z0-9._-]+", "_", f"{job.policy}-{variant.suite}-{variant.label}")
    return f"{readable[-80:]}-{job.first:05d}-{digest}"


def _model_digest(policy: str) -> str | None:
    """SHA-256 of a learned model's ``model.zip`` (``None`` for an analytic policy)."""
    from agents.learned import MODELS_DIR

    for directory in (Path(policy), MODELS_DIR / policy):
        path = directory / "model.zip" if directory.suffix != ".zip" else directory
        if path.is_file():
            stat = path.stat()
            return _file_digest(str(path.resolve()), stat.st_mtime_ns, stat.st_size)
    return None


@functools.lru_cache(maxsize=64)
def _file_digest(path: str, mtime_ns: int, size: int) -> str:
    """Hash the file (SHA-256; cached while its time stamp and size stay the same)."""
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


class ChunkStore:
    """The finished chunks of a benchmark, one JSON file each under ``directory``.

    Parameters
    ----------
    directory
        Where the chunk files live (created on the first save).
    """

    def __init__(self, directory: Path | str) -> None:
        self.directory = Path(directory)

    def path(self, job: Job) -> Path:
        """Return the job's file."""
        return self.directory / f"{job_key(job)}.json"

    def load(self, job: Job) -> JobResult | None:
        """Return the job's stored result, or ``None`` if not done (or its file is unreadable)."""
        path = self.path(job)
        if not path.is_file():
            return None
        try:
            data = json.loads(path.read_text())
            paths = [(p[0], np.asarray(p[1], dtype=np.float64)) for p in data["paths"]]
            return JobResult(job, list(data["rows"]), paths, data.get("skipped"))
        except (OSError, ValueError, KeyError, TypeError, IndexError):
            return None  # a damaged file: the chunk runs again

    def save(self, result: JobResult) -> Path:
        """Write a finished job's result (atomically)."""
        data: dict[str, Any] = {
            "rows": result.rows,  # plain Python values: JSON keeps every float exactly
            "paths": [[task, np.asarray(xy).tolist()] for task, xy in result.paths],
            "skipped": result.skipped,
        }
        return write_json(self.path(result.job), data)
