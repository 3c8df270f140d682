"""The benchmark's plots: success per suite, the domain of convergence, paths side by side."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from radial_ibvs_agents.plotting import pyplot, save_figure
from radial_ibvs_gym.geometry import relative_pose

if TYPE_CHECKING:
    from radial_ibvs_agents.experiments.jobs import JobResult

__all__ = [
    "draw_convergence_map",
    "plot_convergence_map",
    "plot_success",
    "plot_success_curves",
    "plot_trajectories",
    "starts_in_goal_frame",
    "success_curve",
]


def plot_success(summaries: Sequence[dict[str, Any]], path: Path) -> Path:
    """Draw a heat map: the success rate (and its 95 % interval) of each policy per variant.

    One row per suite variant, one column per policy; each cell shows the success rate and,
    below it, its 95 % Wilson interval. Missing cells (a model that does not fit a variant's
    observations) are blank.
    """
    plt = pyplot()
    policies = list(dict.fromkeys(s["policy"] for s in summaries))
    groups = list(dict.fromkeys((s["suite"], s["variant"]) for s in summaries))
    index = {(s["suite"], s["variant"], s["policy"]): s for s in summaries}
    rate = np.full((len(groups), len(policies)), np.nan)
    for g, (suite, variant) in enumerate(groups):
        for p, policy in enumerate(policies):
            if (suite, variant, policy) in index:
                rate[g, p] = index[(suite, variant, policy)]["success_rate"]
    fig, ax = plt.subplots(figsize=(1.1 * len(policies) + 2.8, 0.42 * len(groups) + 1.6))
    ax.imshow(np.ma.masked_invalid(rate), cmap="RdYlGn", vmin=0.0, vmax=1.0, aspect="auto")
    for g, (suite, variant) in enumerate(groups):
        for p, policy in enumerate(policies):
            s = index.get((suite, variant, policy))
            if s is None:
                continue
            lo, hi = s["success_ci95"]
            ink = "white" if not 0.15 <= s["success_rate"] <= 0.85 else "black"
            ax.text(
                p,
                g - 0.12,
                f"{100 * s['success_rate']:.0f}%",
                ha="center",
                va="center",
                fontsize=8,
                weight="bold",
                color=ink,
            )
            ax.text(
                p,
                g + 0.25,
                f"{100 * lo:.0f}-{100 * hi:.0f}",
                ha="center",
                va="center",
                fontsize=5.5,
                color=ink,
            )
    ax.set_xticks(range(len(policies)))
    ax.set_xticklabels(policies, rotation=30, ha="right", fontsize=8)
    ax.set_yticks(range(len(groups)))
    ax.set_yticklabels([f"{suite}: {variant}" for suite, variant in groups], fontsize=8)
    ax.set_title("success rate per suite variant (small: 95% interval)", fontsize=9)
    fig.tight_layout()
    return save_figure(fig, path)


def success_curve(
    rows: Sequence[Mapping[str, Any]], key: str, tolerances: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Return the fraction of ``rows`` whose final ``key`` error is within each tolerance.

    Parameters
    ----------
    rows
        Benchmark rows with ``final_position_error_m`` and ``final_heading_error_deg``.
    key
        ``"final_position_error_m"`` (metres) or ``"final_heading_error_deg"`` (degrees).
    tolerances
        ``(T,)`` tolerances, in the key's unit.

    Returns
    -------
    numpy.ndarray
        ``(T,)`` in ``[0, 1]``; an episode that ended in a collision counts as outside every
        tolerance (its final pose is where it hit, not where it parked).
    """
    errors = np.array(
        [np.inf if r.get("collision") else float(r[key]) for r in rows], dtype=np.float64
    )
    if not len(errors):
        return np.full(len(tolerances), np.nan)
    return (errors[None, :] <= np.asarray(tolerances)[:, None]).mean(axis=1)


def plot_success_curves(
    rows: Sequence[Mapping[str, Any]], path: Path, policies: Sequence[str] | None = None
) -> Path:
    """Draw success curves: the share of episodes parked within a tolerance, as it grows.

    Two panels over every row given (choose the suites before): the final position error
    (centimetres, 0.5 to 100, log scale) and the final heading error (degrees, 0.2 to 90). A
    curve that rises early parks precisely; its height at the right is how often the robot
    got near at all. The dotted lines are the benchmark's tolerance (2 cm, 2 deg).

    Raises
    ------
    ValueError
        If no row has the final errors.
    """
    keys = ("final_position_error_m", "final_heading_error_deg")
    rows = [r for r in rows if all(k in r for k in keys)]
    if not rows:
        raise ValueError("no rows with final_position_error_m and final_heading_error_deg")
    plt = pyplot()
    shown = list(policies or dict.fromkeys(str(r["policy"]) for r in rows))
    fig, axes = plt.subplots(1, 2, figsize=(10.0, 4.0))
    panels = (
        ("final_position_error_m", np.geomspace(0.005, 1.0, 120), 100.0, "position (cm)", 2.0),
        ("final_heading_error_deg", np.geomspace(0.2, 90.0, 120), 1.0, "heading (deg)", 2.0),
    )
    for ax, (key, tolerances, scale, label, mark) in zip(axes, panels, strict=True):
        for policy in shown:
            mine = [r for r in rows if r["policy"] == policy]
            if mine:
                dashed = policy.startswith("planner")
                ax.plot(
                    scale * tolerances,
                    success_curve(mine, key, tolerances),
                    "--" if dashed else "-",
                    label=policy,
                )
        ax.axvline(mark, color="grey", linestyle=":", linewidth=1)
        ax.set_xscale("log")
        ax.set_ylim(0.0, 1.02)
        ax.set_xlabel(f"tolerance, final {label}")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("episodes within the tolerance")
    axes[1].legend(fontsize=7, loc="upper left")
    fig.suptitle(f"success curves ({len(rows)} episodes; dashed: the limits)", fontsize=10)
    fig.tight_layout()
    return save_figure(fig, path)


def plot_convergence_map(rows: Sequence[dict[str, Any]], path: Path) -> Path:
    """Start positions of the ``random`` suite in the goal's frame, by outcome, one panel each."""
    plt = pyplot()
    rows = [r for r in rows if r["suite"] == "random"]
    policies = list(dict.fromkeys(r["policy"] for r in rows))
    fig, axes = plt.subplots(1, len(policies), figsize=(3.6 * len(policies), 3.8), squeeze=False)
    for k, (ax, policy) in enumerate(zip(axes[0], policies, strict=True)):
        draw_convergence_map(ax, [r for r in rows if r["policy"] == policy], policy)
        if k:
            ax.set_ylabel("")
    axes[0, 0].legend(fontsize=7, loc="lower left")
    fig.suptitle("domain of convergence (random rooms; the goal at the origin, heading +x)")
    fig.tight_layout()
    return save_figure(fig, path)


def starts_in_goal_frame(
    rows: Sequence[Mapping[str, Any]],
) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Start positions in the frame of each episode's goal, and whether the robot parked.

    Parameters
    ----------
    rows
        Benchmark rows (:func:`~radial_ibvs_agents.experiments.benchmark.run_benchmark`) with
        ``start_pose``, ``goal_pose`` (``(x, y, yaw)``, metres and radians) and ``success``.

    Returns
    -------
    xy
        ``(K, 2)`` start positions with the goal at the origin heading along +x, metres.
    success
        ``(K,)`` whether each episode parked.
    """
    if not rows:
        return np.zeros((0, 2)), np.zeros(0, dtype=bool)
    start = np.array([r["start_pose"] for r in rows], dtype=np.float64)
    goal = np.array([r["goal_pose"] for r in rows], dtype=np.float64)
    xy = relative_pose(goal, start)[:, :2]  # the start seen from the goal
    return xy, np.array([bool(r["success"]) for r in rows])


def draw_convergence_map(ax: Any, rows: Sequence[Mapping[str, Any]], title: str = "") -> float:
    """Draw start positions in the goal's frame, green where the robot parked, red where not.

    Parameters
    ----------
    ax
        Matplotlib axes (equal aspect, metres).
    rows
        Benchmark rows of one policy (see :func:`starts_in_goal_frame`).
    title
        Axes title; the success rate is appended.

    Returns
    -------
    float
        The success rate (NaN without rows).
    """
    xy, success = starts_in_goal_frame(rows)
    for mask, marker, color, label in (
        (success, "o", "C2", "parked"),
        (~success, "x", "C3", "failed"),
    ):
        if mask.any():
            ax.scatter(xy[mask, 0], xy[mask, 1], s=14, marker=marker, color=color, label=label)
    ax.plot(0.0, 0.0, "ks", ms=6)
    ax.arrow(0.0, 0.0, 0.6, 0.0, width=0.04, color="k", lw=0)
    rate = float(success.mean()) if len(success) else math.nan
    ax.set_title(f"{title}: {rate:.0%} of {len(success)}" if title else f"{rate:.0%}")
    ax.set_aspect("equal")
    ax.set_xlabel("start x in the goal frame [m]")
    ax.set_ylabel("start y in the goal frame [m]")
    ax.grid(alpha=0.3)
    return rate


def plot_trajectories(results: Sequence[JobResult], path: Path) -> Path:
    """Paths of every policy on the paper's four tasks (exact depths), side by side."""
    plt = pyplot()
    mine = [r for r in results if r.job.variant.label == "d*"]
    tasks = sorted({task for r in mine for task, _ in r.paths if task is not None})
    fig, axes = plt.subplots(1, len(tasks), figsize=(3.6 * len(tasks), 3.8), squeeze=False)
    for ax, task in zip(axes[0], tasks, strict=True):
        for p, result in enumerate(mine):
            for t, xy in result.paths:
                if t == task:
                    ax.plot(xy[:, 0], xy[:, 1], color=f"C{p % 10}", label=result.job.policy)
                    break
        ax.plot(3.0, 3.0, "ko", ms=4)
        ax.plot(7.0, 7.0, "ks", ms=5)
        ax.set_title(f"paper-sim task {task} (goal yaw {90 * task} deg)")
        ax.set_aspect("equal")
        ax.set_xlim(0, 15.6)
        ax.set_ylim(0, 15.6)
        ax.grid(alpha=0.3)
    axes[0, 0].legend(fontsize=7)
    fig.tight_layout()
    return save_figure(fig, path)
