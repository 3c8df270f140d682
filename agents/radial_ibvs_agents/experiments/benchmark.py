"""``radial-ibvs benchmark``: every policy on the same suites, seeds and metrics.

Jobs (one per policy, suite variant and chunk of at most 100 seeded episodes) run in parallel
processes or as Ray tasks (:mod:`radial_ibvs_agents.experiments.backends`), and each finished chunk
can be saved at once, so that a rerun resumes (:mod:`radial_ibvs_agents.experiments.store`). Each
episode gives a row (the JSON contract of ``--json`` plus ``variant``, control effort, smoothness
and the start and goal poses); the summary gives, per policy and variant, the success rate with its
95 % Wilson interval, the median and 95th percentile of the final errors, the time and path to park,
the effort, smoothness, collisions and compute time per step.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
from tqdm import tqdm  # text bars: no ipywidgets needed in Jupyter

from radial_ibvs_agents import make_policy
from radial_ibvs_agents.experiments.backends import LocalBackend, RayBackend, make_backend
from radial_ibvs_agents.experiments.jobs import CHUNK, Job, JobResult, init_worker, run_job
from radial_ibvs_agents.experiments.store import ChunkStore
from radial_ibvs_agents.experiments.suites import Variant, suite_variants
from radial_ibvs_agents.experiments.tables import markdown_table, write_rows_csv
from radial_ibvs_agents.io import write_atomic, write_json
from radial_ibvs_agents.rows import add_limits, judging_rules, load_rows, summarise
from radial_ibvs_gym.envs.config import MAX_HOLD_STEPS, ParkingConfig
from radial_ibvs_gym.envs.rules import park_hold_steps

__all__ = [
    "Job",
    "JobResult",
    "job_cost",
    "run_benchmark",
    "suite_timings",
    "summary_rows",
    "write_outputs",
]


def run_benchmark(
    policies: Sequence[str],
    suites: Sequence[str],
    episodes: int | None = None,
    workers: int = 1,
    progress: bool = True,
    *,
    backend: str | LocalBackend | RayBackend = "local",
    address: str | None = None,
    store: Path | str | None = None,
    notify: Callable[[str], None] | None = None,
    trust_model: bool = False,
    success_hold_steps: int | None = None,
) -> list[JobResult]:
    """Run every policy on every suite variant, in chunks of at most :data:`CHUNK` episodes.

    Parameters
    ----------
    policies
        Policy names (:func:`radial_ibvs_agents.make_policy`: analytic ones, shipped models,
        directories).
    suites
        Suite names (:data:`radial_ibvs_agents.experiments.suites.SUITES`).
    episodes
        Episodes per variant (default: the variant's own, 200 for ``random`` and 8 otherwise).
    workers
        Parallel processes (1: run here); for a private Ray instance, its CPUs.
    progress
        Show a progress bar.
    backend
        ``"local"`` (a process pool), ``"ray"`` (one Ray task per chunk, retried when its
        worker dies), or a backend object (:mod:`radial_ibvs_agents.experiments.backends`).
    address
        Ray cluster address (``"auto"`` or ``"HOST:PORT"``); default: a private instance.
    store
        A folder where each finished chunk is saved at once
        (:class:`~radial_ibvs_agents.experiments.store.ChunkStore`); the chunks already there are
        loaded, not run again. ``None``: nothing is saved.
    notify
        Called with a line of text about resuming (e.g. ``print``).
    trust_model
        Load model directories that hold only a pickled stable-baselines3 ``model.zip``
        (:func:`radial_ibvs_agents.learned.load`'s ``trust_pickle``), in every worker.
    success_hold_steps
        How many steps in a row the pose must stay within the tolerances for a success
        (the env's ``success_hold_steps``), for every policy alike. ``None``, the default: a
        park, held 1 s (10 steps of 0.1 s); 1: the older rule, the first step within them. The
        rule is part of every job's key, so no chunk judged by one is reused for another.

    Returns
    -------
    list of JobResult
        One per policy and variant, its rows in seed order. The rows do not depend on the
        backend, the workers or on resuming, except ``compute_us_per_step`` (a timing) and
        ``compute_batch`` (how many robots one call served, which the chunking sets).

    Raises
    ------
    ValueError
        For an unknown policy, suite or backend, or Ray missing (checked before anything
        runs).
    """
    for name in policies:
        make_policy(name, trust_pickle=trust_model)  # fail early, with the valid names
    if workers < 1:
        raise ValueError(f"workers must be >= 1, got {workers!r}")
    if episodes is not None and episodes < 1:
        raise ValueError(f"episodes must be >= 1, got {episodes!r}")
    if success_hold_steps is not None and (
        isinstance(success_hold_steps, bool)
        or not (isinstance(success_hold_steps, int) and 1 <= success_hold_steps <= MAX_HOLD_STEPS)
    ):
        raise ValueError(
            f"success_hold_steps must be an integer in 1..{MAX_HOLD_STEPS}, "
            f"got {success_hold_steps!r}"
        )
    variants = suite_variants(list(suites))
    # the judging rule, in steps, is part of every variant, so of every job's key
    variants = [
        replace(v, overrides={**v.overrides, "success_hold_steps": _hold(v, success_hold_steps)})
        for v in variants
    ]
    jobs = [
        Job(policy, variant, min(CHUNK, total - first), first, trust_model)
        for variant in variants
        for policy in policies
        for total in [episodes or variant.episodes]
        for first in range(0, total, CHUNK)
    ]
    chunks = ChunkStore(store, notify) if store is not None else None
    results: list[JobResult | None] = [chunks.load(j) if chunks else None for j in jobs]
    # the costliest jobs first, so the pool does not end waiting on one long job
    todo = sorted((i for i, r in enumerate(results) if r is None), key=lambda i: -job_cost(jobs[i]))
    if chunks is not None and notify is not None and len(todo) < len(jobs):
        notify(
            f"resuming: {len(jobs) - len(todo)} of {len(jobs)} chunks already done in "
            f"{chunks.directory}, skipping them; {len(todo)} to run"
        )
    runner = make_backend(backend, workers, address) if isinstance(backend, str) else backend
    bar = tqdm(
        total=sum(jobs[i].episodes for i in todo), desc="benchmark", unit="ep", disable=not progress
    )
    try:
        for k, result in runner.imap_unordered(run_job, [jobs[i] for i in todo], init_worker):
            results[todo[k]] = result
            if chunks is not None:
                chunks.save(result)
            bar.update(result.job.episodes)
    finally:
        bar.close()
        if isinstance(backend, str):
            runner.close()
    return _merge([r for r in results if r is not None])


def _hold(variant: Variant, hold_steps: int | None) -> int:
    """Return the steps a variant's success holds: ``hold_steps``, or 1 s at its period."""
    if hold_steps is not None:
        return hold_steps
    default = dataclasses.fields(ParkingConfig)
    control_dt = next(f.default for f in default if f.name == "control_dt")
    return park_hold_steps(float(variant.overrides.get("control_dt", control_dt)))


def job_cost(job: Job) -> float:
    """Return a job's expected cost in episodes through an ideal camera (to order the jobs).

    Rendering and detecting an image at every step costs about 50 times that (one robot at a
    time), and a camera with imperfections about 5 times (an exact projection per landmark).
    """
    overrides = job.variant.overrides
    camera = overrides.get("camera") or {}
    if overrides.get("measurement") == "detected":
        weight = 50.0
    elif "imperfections" in camera or "imperfection_ranges" in camera:
        weight = 5.0
    else:
        weight = 1.0
    return weight * job.episodes


def _merge(chunks: Sequence[JobResult]) -> list[JobResult]:
    """One result per (policy, variant), its chunks' rows and paths in episode order."""
    merged: dict[tuple[str, str, str], JobResult] = {}
    for r in sorted(chunks, key=lambda r: r.job.first):
        key = (r.job.policy, r.job.variant.suite, r.job.variant.label)
        if key not in merged:
            merged[key] = JobResult(Job(r.job.policy, r.job.variant, 0), [], [], r.skipped, 0.0)
        m = merged[key]
        m.rows.extend(r.rows)
        m.paths.extend(r.paths)
        m.wall_s = (m.wall_s or 0.0) + (r.wall_s or 0.0)  # the chunks run now
        m.resumed += r.resumed
        m.job = Job(r.job.policy, r.job.variant, m.job.episodes + r.job.episodes)
    return list(merged.values())  # the jobs' order: first chunks come first, stably sorted


def summary_rows(results: Sequence[JobResult]) -> list[dict[str, Any]]:
    """One summary per policy and variant (``rows.summarise``), with effort and limits."""
    out = []
    for result in results:
        if result.skipped:
            continue
        summary = summarise(result.rows)
        summary.update(
            policy=result.job.policy,
            suite=result.job.variant.suite,
            variant=result.job.variant.label,
            physics=", ".join(sorted({str(r["physics"]) for r in result.rows})),
            control_effort=float(np.mean([r["control_effort"] for r in result.rows])),
            smoothness=float(np.mean([r["smoothness"] for r in result.rows])),
        )
        out.append(summary)
    add_limits(out)  # the limits beside every policy: the planners' rates
    return out


def suite_timings(results: Sequence[JobResult]) -> list[dict[str, Any]]:
    """Return the worker-seconds each suite's jobs took, per suite and in all.

    A job's time is measured in its worker; with several workers the wall clock is about the
    total divided by the workers. Chunks loaded from saved ones (a resumed run) have no time
    and are counted apart (``resumed``); a skipped job counts the time it took to say so.
    """
    suites: dict[str, dict[str, Any]] = {}
    for r in results:
        entry = suites.setdefault(
            r.job.variant.suite, {"suite": r.job.variant.suite, "seconds": 0.0, "episodes": 0,
                                  "jobs": 0, "resumed": 0},
        )  # fmt: skip
        entry["episodes"] += len(r.rows)
        entry["resumed"] += r.resumed
        if r.wall_s is not None:
            entry["seconds"] += r.wall_s
            entry["jobs"] += 1
    return sorted(suites.values(), key=lambda e: -e["seconds"])


def earlier_rows(
    out_dir: Path | str, results: Sequence[JobResult]
) -> tuple[list[dict[str, Any]], str | None]:
    """Return the rows of ``out_dir/episodes.json`` that this run did not make, and a note.

    A rerun into the same ``--out`` with fewer policies or suites keeps the other rows of the
    earlier run (read as data: :func:`~radial_ibvs_agents.rows.load_rows`). They are kept only
    when judged as this run's rows; otherwise the note says why they are left out.
    """
    path = Path(out_dir) / "episodes.json"
    if not path.is_file():
        return [], None
    made = {(r.job.policy, r.job.variant.suite, r.job.variant.label) for r in results}
    try:
        rows = load_rows([path])
    except ValueError as error:
        return [], f"earlier rows of {path} not kept: {str(error)[:200]}"
    kept = [r for r in rows if (r["policy"], r["suite"], r["variant"]) not in made]
    ours = {row.get("success_hold_steps", 1) for result in results for row in result.rows}
    if kept and ours and {r.get("success_hold_steps", 1) for r in kept} != ours:
        return [], f"earlier rows of {path} not kept: they were judged differently"
    if not kept:
        return [], None
    policies = sorted({str(r["policy"]) for r in kept})
    return kept, f"kept {len(kept)} rows of an earlier run in {path} (policies {policies})"


def write_outputs(results: Sequence[JobResult], out_dir: Path | str) -> list[Path]:
    """Write ``episodes.csv``, ``episodes.json``, ``summary.md`` and the plots into ``out_dir``.

    ``episodes.json`` and ``episodes.csv`` keep the rows of an earlier run into the same folder
    that this run did not make (:func:`earlier_rows`); the summary and plots are this run's.
    """
    out = Path(out_dir)
    kept, note = earlier_rows(out, results)
    if note:
        print(note)
    rows = [row for result in results for row in result.rows]
    summaries = summary_rows(results)
    skipped = [
        f"- {r.job.policy} on {r.job.variant.suite}/{r.job.variant.label}: {r.skipped}"
        for r in results
        if r.skipped
    ]
    rules = "; ".join(judging_rules(rows)) or "none run"
    table = f"Success: {rules}.\n\n" + markdown_table(summaries)
    if skipped:
        table += "\nSkipped:\n" + "\n".join(skipped) + "\n"
    written = [
        write_rows_csv(out / "episodes.csv", [*kept, *rows]),
        write_json(out / "episodes.json", [*kept, *rows]),
        write_atomic(out / "summary.md", table),
    ]
    from radial_ibvs_agents.experiments.benchmark_plots import (
        plot_convergence_map,
        plot_success,
        plot_trajectories,
    )

    if summaries:
        written.append(plot_success(summaries, out / "success_by_suite.png"))
    if any(r["suite"] == "random" for r in rows):
        written.append(plot_convergence_map(rows, out / "convergence_map.png"))
    paper = [r for r in results if r.job.variant.suite == "paper" and r.paths and not r.skipped]
    if paper:
        written.append(plot_trajectories(paper, out / "trajectories.png"))
    return written
