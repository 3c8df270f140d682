"""Aggregate scores across training seeds as RL researchers report them (Agarwal et al. 2021).

The interquartile mean (IQM: the mean of the middle 50 % of the scores) is robust to a few
outlier seeds and more efficient than the median; its uncertainty is a stratified bootstrap
interval: the seeds of each task (suite) are resampled with replacement, independently of the
other tasks'. scipy does both (``trim_mean``; ``bootstrap`` with independent samples).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike
from scipy import stats

__all__ = ["iqm", "iqm_interval"]


def iqm(scores: ArrayLike) -> float:
    """Interquartile mean of ``scores`` (any shape, flattened); NaN when empty."""
    values = np.asarray(scores, dtype=np.float64).ravel()
    return float(stats.trim_mean(values, 0.25)) if values.size else math.nan


def iqm_interval(
    scores_by_task: Sequence[ArrayLike],
    confidence: float = 0.95,
    n_resamples: int = 2000,
    seed: int = 0,
) -> tuple[float, float, float]:
    """IQM across every task's seeds, with a stratified-bootstrap confidence interval.

    Parameters
    ----------
    scores_by_task
        One array of per-seed scores (e.g. success rates in ``[0, 1]``) per task.
    confidence
        Confidence level of the interval.
    n_resamples
        Bootstrap resamples.
    seed
        Seed of the resampling (the same seed, the same interval).

    Returns
    -------
    tuple of float
        ``(iqm, low, high)``; ``low`` and ``high`` are NaN when a task has fewer than two
        seeds (no interval from one run).

    Raises
    ------
    ValueError
        For no tasks, an empty task, or a confidence outside ``(0, 1)``.
    """
    samples = [np.asarray(s, dtype=np.float64).ravel() for s in scores_by_task]
    if not samples or any(s.size == 0 for s in samples):
        raise ValueError("iqm_interval needs at least one score per task")
    if not 0.0 < confidence < 1.0:
        raise ValueError(f"confidence must be in (0, 1), got {confidence!r}")
    point = iqm(np.concatenate(samples))
    if any(s.size < 2 for s in samples):
        return point, math.nan, math.nan
    if all(np.all(s == samples[0][0]) for s in samples):
        return point, point, point  # no spread: every resample gives the same IQM
    result = stats.bootstrap(
        tuple(samples),
        lambda *resampled: iqm(np.concatenate(resampled)),
        paired=False,  # independent resampling per task: the stratified bootstrap
        vectorized=False,
        confidence_level=confidence,
        n_resamples=n_resamples,
        method="percentile",
        rng=np.random.default_rng(seed),
    )
    low, high = result.confidence_interval
    return point, float(low), float(high)
