"""``radial-ibvs benchmark``: every policy on the same suites, seeds and metrics.

Jobs (one per policy and suite variant) run in parallel processes. Each episode gives a row
(the JSON contract of ``--json`` plus ``variant``, control effort, smoothness and the start and
goal poses); the summary gives, per policy and variant, the success rate with its 95 % Wilson
interval, the median and 95th percentile of the final errors, the time and path to park, the
effort, smoothness, collisions and compute time per step.
"""

from __future__ import annotations

import math
import multiprocessing
from collections.abc import Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path
from typing import Any

import numpy as np
from tqdm import tqdm  # text bars: no ipywidgets needed in Jupyter

from agents import make_policy
from agents.experiments.evaluate import summarise
from agents.experiments.jobs import CHUNK, Job, JobResult, init_worker, run_job
from agents.experiments.suites import suite_variants
from agents.io import write_atomic, write_csv, write_json

__all__ = [
    "Job",
    "JobResult",
    "markdown_table",
    "rich_table",
    "run_benchmark",
    "summary_rows",
    "write_outputs",
]


def run_benchmark(
    policies: Sequence[str],
    suites: Sequence[str],
    episodes: int | None = None,
    workers: int = 1,
    progress: bool = True,
) -> list[JobResult]:
    """Run every policy on every suite variant.

    Parameters
    ----------
    policies
        Policy names (:func:`agents.make_policy`: analytic ones, shipped models, directories).
    suites
        Suite names (:data:`agents.experiments.suites.SUITES`).
    episodes
        Episodes per variant (default: the variant's own, 200 for ``random`` and 8 otherwise).
    workers
        Parallel processes (1: run here).
    progress
        Show a progress bar.

    Raises
    ------
    ValueError
        For an unknown policy or suite (checked before anything runs).
    """
    for name in policies:
        make_policy(name)  # fail early, with the valid names
    if workers < 1:
        raise ValueError(f"workers must be >= 1, got {workers!r}")
    if episodes is not None and episodes < 1:
        raise ValueError(f"episodes must be >= 1, got {episodes!r}")
    jobs = [
        Job(policy, variant, min(CHUNK, total - first), first)
        for variant in suite_variants(list(suites))
        for policy in policies
        for total in [episodes or variant.episodes]
        for first in range(0, total, CHUNK)
    ]
    bar = tqdm(
        total=sum(j.episodes for j in jobs), desc="benchmark", unit="ep", disable=not progress
    )
    results: list[JobResult | None] = [None] * len(jobs)
    if workers == 1:
        for i, job in enumerate(jobs):
            results[i] = run_job(job)
            bar.update(job.episodes)
    else:
        # spawn, not fork: torch (loaded here to check the models) hangs in forked children
        context = multiprocessing.get_context("spawn")
        with ProcessPoolExecutor(workers, mp_context=context, initializer=init_worker) as pool:
            futures = {pool.submit(run_job, job): i for i, job in enumerate(jobs)}
            for future in as_completed(futures):
                results[futures[future]] = future.result()
                bar.update(jobs[futures[future]].episodes)
    bar.close()
    return _merge([r for r in results if r is not None])


def _merge(chunks: Sequence[JobResult]) -> list[JobResult]:
    """One result per (policy, variant), its chunks' rows and paths in episode order."""
    merged: dict[tuple[str, str, str], JobResult] = {}
    for r in sorted(chunks, key=lambda r: r.job.first):
        key = (r.job.policy, r.job.variant.suite, r.job.variant.label)
        if key not in merged:
            merged[key] = JobResult(Job(r.job.policy, r.job.variant, 0), [], [], r.skipped)
        m = merged[key]
        m.rows.extend(r.rows)
        m.paths.extend(r.paths)
        m.job = Job(r.job.policy, r.job.variant, m.job.episodes + r.job.episodes)
    return list(merged.values())  # the jobs' order: first chunks come first, stably sorted


def summary_rows(results: Sequence[JobResult]) -> list[dict[str, Any]]:
    """One summary per policy and variant (see :func:`~.evaluate.summarise`), plus effort."""
    out = []
    for result in results:
        if result.skipped:
            continue
        summary = summarise(result.rows)
        summary.update(
            policy=result.job.policy,
            suite=result.job.variant.suite,
            variant=result.job.variant.label,
            control_effort=float(np.mean([r["control_effort"] for r in result.rows])),
            smoothness=float(np.mean([r["smoothness"] for r in result.rows])),
        )
        out.append(summary)
    return out


def _fmt(value: float, scale: float = 1.0, digits: int = 2) -> str:
    return "-" if value is None or not math.isfinite(value) else f"{scale * value:.{digits}f}"


def markdown_table(summaries: Sequence[dict[str, Any]]) -> str:
    """Format the summaries as a Markdown table."""
    lines = [
        "| suite | variant | policy | success | 95% CI | pos. err. median / p95 [cm] "
        "| head. err. median / p95 [deg] | time [s] | path [m] | effort | smooth. "
        "| coll. | us/step |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for s in summaries:
        lo, hi = s["success_ci95"]
        lines.append(
            f"| {s['suite']} | {s['variant']} | {s['policy']} | {s['success_rate']:.0%} "
            f"| {lo:.0%}-{hi:.0%} "
            f"| {_fmt(s['position_error_m_median'], 100)} / {_fmt(s['position_error_m_p95'], 100)} "
            f"| {_fmt(s['heading_error_deg_median'])} / {_fmt(s['heading_error_deg_p95'])} "
            f"| {_fmt(s['time_s_median'], digits=1)} | {_fmt(s['path_m_median'])} "
            f"| {_fmt(s['control_effort'])} | {_fmt(s['smoothness'], digits=3)} "
            f"| {s['collisions']} | {_fmt(s['compute_us_per_step'], digits=0)} |"
        )
    return "\n".join(lines) + "\n"


def rich_table(summaries: Sequence[dict[str, Any]]) -> Any:
    """Build a compact ``rich`` table for the terminal (the full one is ``summary.md``)."""
    from rich.table import Table

    table = Table(title="benchmark (full table: summary.md)")
    for name in (
        "suite / variant",
        "policy",
        "success (95% CI)",
        "pos. err. [cm]",
        "head. err. [deg]",
        "time [s]",
        "coll.",
    ):
        table.add_column(name, justify="left" if name in ("suite / variant", "policy") else "right")
    for s in summaries:
        lo, hi = s["success_ci95"]
        table.add_row(
            f"{s['suite']} / {s['variant']}",
            s["policy"],
            f"{s['success_rate']:.0%} ({lo:.0%}-{hi:.0%})",
            _fmt(s["position_error_m_median"], 100),
            _fmt(s["heading_error_deg_median"]),
            _fmt(s["time_s_median"], digits=1),
            str(s["collisions"]),
        )
    return table


_CSV_COLUMNS = (
    "policy",
    "scenario",
    "suite",
    "variant",
    "task",
    "seed",
    "physics",
    "success",
    "final_position_error_m",
    "final_heading_error_deg",
    "steps",
    "time_s",
    "path_length_m",
    "collision",
    "compute_us_per_step",
    "control_effort",
    "smoothness",
)


def write_outputs(results: Sequence[JobResult], out_dir: Path | str) -> list[Path]:
    """Write ``episodes.csv``, ``episodes.json``, ``summary.md`` and the plots into ``out_dir``."""
    out = Path(out_dir)
    rows = [row for result in results for row in result.rows]
    summaries = summary_rows(results)
    skipped = [
        f"- {r.job.policy} on {r.job.variant.suite}/{r.job.variant.label}: {r.skipped}"
        for r in results
        if r.skipped
    ]
    table = markdown_table(summaries)
    if skipped:
        table += "\nSkipped:\n" + "\n".join(skipped) + "\n"
    written = [
        write_csv(out / "episodes.csv", rows, _CSV_COLUMNS),
        write_json(out / "episodes.json", rows),
        write_atomic(out / "summary.md", table),
    ]
    from agents.experiments.benchmark_plots import (
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
