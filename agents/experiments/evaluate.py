"""``radial-ibvs evaluate``: run one policy on a scenario for a number of seeded episodes."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from tqdm import tqdm  # text bars: no ipywidgets needed in Jupyter

from agents import make_policy
from agents.experiments.batched import batch_mode, batchable, run_batch
from agents.runner import DEFAULT_ENV_ID, EpisodeLog, env_kwargs_for, make_env, run_episode
from radial_ibvs_gym.config import read_yaml, short

__all__ = ["evaluate", "parse_env_kwargs", "summarise", "wilson_interval"]


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
    """Run ``episodes`` episodes seeded ``seed, seed + 1, ...``.

    Batched in the native vector env where :mod:`agents.experiments.batched` can (the same
    episodes as one at a time), else one at a time in a scalar env.

    ``trust_model`` allows a model directory that holds only a pickled stable-baselines3
    ``model.zip`` (:func:`agents.learned.load`'s ``trust_pickle``).

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
    given = env_id or getattr(policy, "env_id", None) or DEFAULT_ENV_ID
    if batchable(given, env_kwargs_for(policy, scenario, overrides)) is None and batch_mode(policy):
        return _batched(policy, policy_name, scenario, overrides, env_id, episodes, seed, suite,
                        progress)  # fmt: skip
    env = make_env(policy, scenario, overrides, env_id=env_id)
    logs = []
    for k in tqdm(range(episodes), desc=policy_name, disable=not progress, unit="ep"):
        log = run_episode(policy, env, seed=seed + k, policy_name=policy_name)
        if suite is not None:
            log.extra["suite"] = suite
        logs.append(log)
    env.close()
    return logs


#: episodes stepped together by :func:`evaluate` (one vector env of this many robots)
BATCH = 100


def _batched(
    policy: Any,
    name: str,
    scenario: str,
    overrides: Mapping[str, Any],
    env_id: str | None,
    episodes: int,
    seed: int,
    suite: str | None,
    progress: bool,
) -> list[EpisodeLog]:
    """:func:`evaluate`'s episodes in batches of :data:`BATCH` (the same episodes, seed by seed)."""
    logs: list[EpisodeLog] = []
    with tqdm(total=episodes, desc=name, disable=not progress, unit="ep") as bar:
        for first in range(seed, seed + episodes, BATCH):
            seeds = list(range(first, min(first + BATCH, seed + episodes)))
            logs += run_batch(policy, seeds, scenario, overrides, env_id=env_id, policy_name=name)
            bar.update(len(seeds))
    for log in logs:
        if suite is not None:
            log.extra["suite"] = suite
    return logs


def wilson_interval(successes: int, n: int, z: float = 1.959963984540054) -> tuple[float, float]:
    """95 % Wilson score interval of a success rate (sound for small ``n`` and 0 or 1 rates)."""
    if n == 0:
        return (math.nan, math.nan)
    p = successes / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    lo = 0.0 if successes == 0 else max(0.0, centre - half)  # exact at the extremes
    hi = 1.0 if successes == n else min(1.0, centre + half)
    return (lo, hi)


def summarise(rows: Sequence[Mapping[str, Any]]) -> dict[str, Any]:
    """Success rate with its 95 % interval, and medians / 95th percentiles of the errors."""
    n = len(rows)
    wins = sum(bool(r["success"]) for r in rows)
    lo, hi = wilson_interval(wins, n)
    pos = np.array([r["final_position_error_m"] for r in rows])
    head = np.array([r["final_heading_error_deg"] for r in rows])
    parked = [r for r in rows if r["success"]]
    return {
        "episodes": n,
        "success_rate": wins / n if n else math.nan,
        "success_ci95": (lo, hi),
        "position_error_m_median": float(np.median(pos)) if n else math.nan,
        "position_error_m_p95": float(np.percentile(pos, 95)) if n else math.nan,
        "heading_error_deg_median": float(np.median(head)) if n else math.nan,
        "heading_error_deg_p95": float(np.percentile(head, 95)) if n else math.nan,
        "time_s_median": float(np.median([r["time_s"] for r in parked])) if parked else math.nan,
        "path_m_median": (
            float(np.median([r["path_length_m"] for r in parked])) if parked else math.nan
        ),
        "collisions": sum(bool(r["collision"]) for r in rows),
        "compute_us_per_step": float(np.mean([r["compute_us_per_step"] for r in rows])),
        "compute_batch": max((int(r.get("compute_batch", 1)) for r in rows), default=1),
        **_tolerances_and_ends(rows),
    }


def _tolerances_and_ends(rows: Sequence[Mapping[str, Any]]) -> dict[str, Any]:
    """Success rate (and Wilson interval) per tolerance, and how the episodes ended."""
    n = len(rows)
    out: dict[str, Any] = {}
    names = [k for k in (rows[0].get("success_by_tolerance") or {})] if rows else []
    if names:
        out["success_by_tolerance"] = {}
        for name in names:
            wins = sum(bool(r["success_by_tolerance"][name]) for r in rows)
            out["success_by_tolerance"][name] = {
                "rate": wins / n,
                "ci95": wilson_interval(wins, n),
            }
    if rows and "end" in rows[0]:
        ends = [str(r["end"]) for r in rows]
        out["ends"] = {e: ends.count(e) for e in ("success", "collision", "lost", "time-out")}
    return out
