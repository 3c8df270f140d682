"""Benchmark results persisted per chunk, so an interrupted run resumes where it stopped.

Each finished job (one policy, one suite variant, a chunk of seeded episodes) is written at
once to ``<out>/chunks/<name>.json`` (atomically: a file is complete or absent). A rerun with
the same ``--out`` loads the chunks already there instead of running them again. A chunk's
file name holds a digest of everything that defines its rows, so a changed job, a retrained
model or an edited scenario is never mistaken for a done one:

- the policy: its name, an analytic policy's settings (gains, radii, robot), and for a
  learned model the bytes of every file of its directory (weights, ``metadata.json`` with
  a residual's settings, normalisation statistics);
- the suite variant: its ``gym.make`` overrides, the seeds and episodes, and the scenario's
  content as loaded (not its name: an edited YAML file changes the key);
- the package version.

A loaded chunk is checked too (its row count, seeds, policy, suite and variant); one that
fails the check runs again, and the store says so.
"""

from __future__ import annotations

import functools
import hashlib
import json
import os
import re
from collections.abc import Callable
from dataclasses import is_dataclass
from pathlib import Path
from typing import Any

import numpy as np

from radial_ibvs_agents import POLICY_NAMES, make_policy
from radial_ibvs_agents.experiments.jobs import Job, JobResult
from radial_ibvs_agents.io import write_atomic
from radial_ibvs_agents.rows import check_row
from radial_ibvs_agents.untrusted import read_json, sha256_file
from radial_ibvs_gym import __version__

__all__ = ["ChunkStore", "job_key"]


def job_key(job: Job, memo: dict[tuple[str, str], Any] | None = None) -> str:
    """Return a file name for the job: readable parts and a digest of its defining fields.

    Parameters
    ----------
    job
        The job.
    memo
        Where to keep each scenario's content, each policy's settings and each model's digest
        once computed (a :class:`ChunkStore` keeps one per run: the 544 jobs of the default
        benchmark read 4 scenario files, not 1,088); ``None``: read them all again.
    """
    memo = {} if memo is None else memo
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
        "model": _once(memo, "model", job.policy, _model_digest),
        "policy_settings": _once(memo, "settings", job.policy, _policy_settings),
        "scenario_content": _once(memo, "scenario", variant.scenario, _scenario_content),
        "version": __version__,
    }
    text = json.dumps(fields, sort_keys=True, default=repr)
    digest = hashlib.sha256(text.encode()).hexdigest()[:12]
    readable = re.sub(r"[^A-Za-z0-9._-]+", "_", f"{job.policy}-{variant.suite}-{variant.label}")
    return f"{readable[-80:]}-{job.first:05d}-{digest}"


def _once(
    memo: dict[tuple[str, str], Any], kind: str, name: str, compute: Callable[[str], Any]
) -> Any:
    """Return ``compute(name)``, computed once per ``memo``."""
    if (kind, name) not in memo:
        memo[kind, name] = compute(name)
    return memo[kind, name]


def _model_digest(policy: str) -> str | None:
    """SHA-256 over every file of a learned model's directory (``None``: not a model)."""
    from radial_ibvs_agents.learned import MODELS_DIR

    for directory in (Path(policy), MODELS_DIR / policy):
        if directory.suffix == ".zip" and directory.is_file():
            directory = directory.parent
        if directory.is_dir():
            total = hashlib.sha256()
            for path in _model_files(directory):
                stat = path.stat()
                digest = _file_digest(str(path), str(directory), stat.st_mtime_ns, stat.st_size)
                total.update(f"{path.relative_to(directory).as_posix()}\0{digest}\0".encode())
            return total.hexdigest()
    return None


#: how deep a model's folder may nest, and how many files it may hold (a digest reads them all)
MAX_MODEL_DEPTH, MAX_MODEL_FILES = 16, 10_000


def _model_files(directory: Path) -> list[Path]:
    """Every regular file of a model's folder, sorted: walked without recursion, bounded.

    Raises
    ------
    ValueError
        For a folder nested deeper than ``MAX_MODEL_DEPTH`` or holding more than
        ``MAX_MODEL_FILES`` files (naming it).
    """
    files: list[Path] = []
    stack = [(directory, 0)]
    while stack:
        folder, depth = stack.pop()
        if depth > MAX_MODEL_DEPTH:
            raise ValueError(f"{directory}: nested deeper than MAX_MODEL_DEPTH = {MAX_MODEL_DEPTH}")
        with os.scandir(folder) as entries:
            for entry in entries:
                if entry.is_dir(follow_symlinks=False):
                    stack.append((Path(entry.path), depth + 1))
                elif entry.is_file():
                    files.append(Path(entry.path))
                    if len(files) > MAX_MODEL_FILES:
                        raise ValueError(
                            f"{directory}: more than MAX_MODEL_FILES = {MAX_MODEL_FILES} files"
                        )
    return sorted(files)


@functools.lru_cache(maxsize=256)
def _file_digest(path: str, folder: str, mtime_ns: int, size: int) -> str:
    """Hash a model's file (SHA-256; cached while its time stamp and size stay the same).

    Read in pieces, at most ``MAX_WEIGHTS_BYTES``, and only inside the model's folder.
    """
    return sha256_file(path, folder)


def _content_digest(key: str, data: dict[str, Any]) -> str:
    """SHA-256 of a chunk's content and its job key (what a stored chunk must match)."""
    text = json.dumps({"key": key, **data}, sort_keys=True, allow_nan=True)
    return hashlib.sha256(text.encode()).hexdigest()


def _policy_settings(policy: str) -> dict[str, Any] | None:
    """Return an analytic policy's settings: its plain attributes (gains, radii, the robot)."""
    if policy not in POLICY_NAMES:
        return None
    return _settings(make_policy(policy))


def _settings(obj: Any, depth: int = 3) -> dict[str, Any]:
    """Return the plain attributes of ``obj``, and those of the policies it wraps."""
    out: dict[str, Any] = {"class": type(obj).__name__}
    for key, value in sorted(vars(obj).items()):
        if key.startswith("_"):
            continue
        if isinstance(value, str | int | float | bool) or value is None or is_dataclass(value):
            out[key] = repr(value)
        elif depth > 0 and hasattr(value, "predict") and hasattr(value, "__dict__"):
            out[key] = _settings(value, depth - 1)
    return out


def _scenario_content(scenario: str) -> str:
    """Return the scenario as loaded (every key, defaults and camera included), as text."""
    from radial_ibvs_gym.scenarios import load_scenario

    return repr(load_scenario(scenario).config)


#: the largest chunk file read back (a chunk holds its episodes' rows and paths)
MAX_CHUNK_BYTES = 64 << 20


class ChunkStore:
    """The finished chunks of a benchmark, one JSON file each under ``directory``.

    Parameters
    ----------
    directory
        Where the chunk files live (created on the first save).
    notify
        Called with a line of text when a chunk file fails its check (e.g. ``print``).

    Notes
    -----
    A store reads each scenario, policy and model once, when it first names a chunk of it (a
    run makes one store): a file edited while a run goes on changes the next run's keys, not
    this one's.
    """

    def __init__(self, directory: Path | str, notify: Callable[[str], None] | None = None) -> None:
        self.directory = Path(directory)
        self.notify = notify
        self._memo: dict[tuple[str, str], Any] = {}

    def path(self, job: Job) -> Path:
        """Return the job's file."""
        return self.directory / f"{job_key(job, self._memo)}.json"

    def load(self, job: Job) -> JobResult | None:
        """Return the job's stored result, or ``None`` if not done (or its file is unreadable)."""
        path = self.path(job)
        if not path.is_file():
            return None
        try:
            data = read_json(path, self.directory, MAX_CHUNK_BYTES)
            content = {k: data[k] for k in ("rows", "paths", "skipped")}
            if data.get("digest") != _content_digest(path.stem, content):
                raise ValueError("its digest does not match its content")
            paths = [(p[0], np.asarray(p[1], dtype=np.float64)) for p in data["paths"]]
            result = JobResult(job, list(data["rows"]), paths, data["skipped"], resumed=1)
            problem = _check(result)
        except (OSError, ValueError, KeyError, TypeError, IndexError, AttributeError) as error:
            problem = f"unreadable: {type(error).__name__}: {str(error)[:120]}"
        if problem is None:
            return result
        if self.notify is not None:
            self.notify(f"chunk {path.name} failed its check ({problem}): running it again")
        return None

    def save(self, result: JobResult) -> Path:
        """Write a finished job's result (atomically)."""
        data: dict[str, Any] = {
            "rows": result.rows,  # plain Python values: JSON keeps every float exactly
            "paths": [[task, np.asarray(xy).tolist()] for task, xy in result.paths],
            "skipped": result.skipped,
        }
        path = self.path(result.job)
        data["digest"] = _content_digest(path.stem, json.loads(json.dumps(data)))
        # compact: json's C encoder (with an indent, json encodes in Python, 5 times slower)
        return write_atomic(path, json.dumps(data) + "\n")


def _check(result: JobResult) -> str | None:
    """Why a loaded chunk's rows are not its job's (``None``: they are)."""
    job, rows = result.job, result.rows
    if result.skipped is not None:
        return None if not rows and isinstance(result.skipped, str) else "skipped, with rows"
    if len(rows) != job.episodes:
        return f"{len(rows)} rows for {job.episodes} episodes"
    for k, row in enumerate(rows):  # rows are data: the schema of every row read
        try:
            check_row(row, f"row {k}")
        except ValueError as error:
            return str(error)[:200]
    seeds = [job.variant.seed_offset + k for k in range(job.first, job.first + job.episodes)]
    if [row.get("seed") for row in rows] != seeds:
        return f"seeds are not {seeds[0]}..{seeds[-1]}"
    for field, expected in (
        ("policy", job.policy),
        ("suite", job.variant.suite),
        ("variant", job.variant.label),
    ):
        if any(row.get(field) != expected for row in rows):
            return f"a row's {field} is not {expected!r}"
    return None
