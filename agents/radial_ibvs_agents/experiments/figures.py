"""Figures in the style of the paper's Fig. 3-4 (paths) and Fig. 6-8 (servoing signals)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any, overload

import numpy as np

from radial_ibvs_agents import IBVSPolicy
from radial_ibvs_agents.plotting import pyplot, save_figure
from radial_ibvs_agents.rollouts.log import EpisodeLog
from radial_ibvs_gym.features import alpha_m, c_ij, virtual_point_weights
from radial_ibvs_gym.geometry import wrap_angle

__all__ = ["plot_paths", "plot_servoing", "servoing_signals"]

_STYLE = {"ibvs": ("C0", "-"), "oracle": ("k", "--"), "ibvs-d1.3": ("C3", "-.")}


@overload
def plot_paths(
    logs: Sequence[EpisodeLog],
    compare: Sequence[str],
    path: Path | str,
    title: str | None = None,
    *,
    axes: Any = None,
    styles: Mapping[str, tuple[str, str]] | None = None,
) -> Path: ...


@overload
def plot_paths(
    logs: Sequence[EpisodeLog],
    compare: Sequence[str],
    path: None = None,
    title: str | None = None,
    *,
    axes: Any = None,
    styles: Mapping[str, tuple[str, str]] | None = None,
) -> None: ...


def plot_paths(
    logs: Sequence[EpisodeLog],
    compare: Sequence[str],
    path: Path | str | None = None,
    title: str | None = None,
    *,
    axes: Any = None,
    styles: Mapping[str, tuple[str, str]] | None = None,
) -> Path | None:
    """Paths of the given cases, one panel per goal yaw (Fig. 3: IBVS vs oracle; Fig. 4: d*).

    Each panel draws the driven paths ``(x, y)`` of the cases on one task, with their start
    (circle) and goal (square) poses and an arrow along each pose's heading, 0.5 m long.

    Parameters
    ----------
    logs
        Episodes of one backend (their ``policy`` labels name the cases, their ``task`` the
        panels: one per task, in increasing order).
    compare
        The case labels to draw, e.g. ``("ibvs", "oracle")``.
    path
        Output image; ``None`` saves nothing (the figure stays open, e.g. to show inline).
    title
        Figure title (the suptitle of the figure drawn in).
    axes
        Matplotlib ``Axes`` to draw into, one per panel (a single ``Axes`` for one task, or a
        sequence or array of them); default: a new figure, ``3.6 x 3.8`` inches a panel.
    styles
        ``case -> (colour, line style)``, over the defaults (``ibvs`` blue solid, ``oracle``
        black dashed, ``ibvs-d1.3`` red dash-dotted; others green dotted).

    Returns
    -------
    pathlib.Path or None
        ``path``, or ``None`` when nothing was saved.

    Raises
    ------
    ValueError
        If ``axes`` does not hold one ``Axes`` per task.
    """
    plt = pyplot()
    drawn = [log for log in logs if log.policy in compare]
    tasks = sorted({log.task for log in drawn if log.task is not None})
    style = {**_STYLE, **(styles or {})}
    if axes is None:
        fig, grid = plt.subplots(1, len(tasks), figsize=(3.6 * len(tasks), 3.8), squeeze=False)
        panels = list(grid[0])
    else:
        panels = list(np.ravel(np.asarray(axes, dtype=object)))
        if len(panels) != len(tasks):
            raise ValueError(f"axes holds {len(panels)} Axes for {len(tasks)} tasks {tasks}")
        fig = panels[0].figure
    for ax, task in zip(panels, tasks, strict=True):
        for log in drawn:
            if log.task != task:
                continue
            color, line = style.get(log.policy, ("C2", ":"))
            ax.plot(*log.poses[:, :2].T, line, color=color, label=log.policy, lw=1.6)
            for pose, marker in ((log.poses[0], "o"), (log.info["goal_pose"], "s")):
                ax.plot(*pose[:2], marker, color="0.3", ms=5)
                ax.arrow(*pose[:2], 0.5 * np.cos(pose[2]), 0.5 * np.sin(pose[2]), width=0.02)
        yaw = round(float(np.degrees(_goal_yaw(drawn, task))))
        ax.set_title(f"goal yaw {yaw % 360} deg")
        ax.set_aspect("equal")
        ax.set_xlabel("x [m]")
        ax.grid(alpha=0.3)
    panels[0].set_ylabel("y [m]")
    panels[0].legend(loc="upper left", fontsize=8)
    if title:
        fig.suptitle(title)
    if axes is None:
        fig.tight_layout()
    return _save(fig, path, close=axes is None)


def _save(fig: Any, path: Path | str | None, close: bool) -> Path | None:
    """Save ``fig`` to ``path`` if one is given (closing it if ``close``); return the path."""
    return None if path is None else save_figure(fig, path, close=close)


def _goal_yaw(logs: Sequence[EpisodeLog], task: int) -> float:
    return float(next(log.info["goal_pose"][2] for log in logs if log.task == task))


def servoing_signals(log: EpisodeLog, lam: float = 0.5) -> dict[str, np.ndarray]:
    """Compute the signals of Fig. 6-8 for one IBVS episode.

    Returns
    -------
    dict
        ``pixel_error`` ``(T + 1, N, 2)`` pixels (current minus goal; NaN where hidden),
        ``c_error`` ``(T + 1, M)`` ``c*_ij - c_ij`` (NaN for pairs with a hidden point),
        ``alpha_m_error`` ``(T + 1,)`` ``alpha*_m - alpha_m`` radians, ``camera_velocity``
        ``(T + 1, 3)`` ``(v_x, v_y, omega_z)`` of the IBVS (m/s, rad/s), ``robot_velocity``
        ``(T, 2)`` the commanded ``(v, omega)`` as fractions of the speed limits.

    Raises
    ------
    ValueError
        When ``log.extra`` has no ``goal_depths`` (the IBVS velocity scales with them).
    """
    goal = log.goal_points
    n = len(goal)
    mask = log.visible
    x = np.where(mask[..., None], log.points, np.array([1.0, 0.0]))
    x = x / np.linalg.norm(x, axis=-1, keepdims=True)
    c_now = c_ij(x)
    i, j = np.triu_indices(n, k=1)
    pair_ok = mask[:, i] & mask[:, j]
    c_error = np.where(pair_ok, c_ij(goal) - c_now, np.nan)
    weights = virtual_point_weights(goal)
    alpha_error = wrap_angle(-alpha_m(x, weights))  # alpha*_m = 0 by construction
    policy = IBVSPolicy(lam=lam)
    if "goal_depths" not in log.extra:
        raise ValueError(
            "servoing_signals needs the goal depths d* in log.extra['goal_depths'] (metres); "
            "reproduce() adds them, or set them from info['goal_depths']"
        )
    depths = np.asarray(log.extra["goal_depths"], dtype=np.float64)
    camera = np.full((len(x), 3), np.nan)
    for k in range(len(x)):
        obs = {
            "points": log.points[k].reshape(-1),
            "goal_points": goal.reshape(-1),
            "visible": mask[k].astype(float),
            "goal_depths": depths,
        }
        estimate = policy.twist(obs)
        if estimate is not None:
            v, gamma = estimate
            camera[k] = (v[0], v[1], lam * gamma)
    pixels = log.extra.get("pixels")
    goal_pixels = log.extra.get("goal_pixels")
    pixel_error = (
        pixels - goal_pixels
        if pixels is not None and goal_pixels is not None
        else np.full((len(x), n, 2), np.nan)
    )
    return {
        "pixel_error": pixel_error,
        "c_error": c_error,
        "alpha_m_error": alpha_error,
        "camera_velocity": camera,
        "robot_velocity": log.actions,
    }


@overload
def plot_servoing(
    log: EpisodeLog, path: Path | str, lam: float = 0.5, *, axes: Any = None
) -> Path: ...


@overload
def plot_servoing(
    log: EpisodeLog, path: None = None, lam: float = 0.5, *, axes: Any = None
) -> None: ...


def plot_servoing(
    log: EpisodeLog, path: Path | str | None = None, lam: float = 0.5, *, axes: Any = None
) -> Path | None:
    """Fig. 6-8 for one episode: image, feature and ``alpha_m`` errors; camera and robot speeds.

    Top: the image point errors (pixels, if the log has them, as
    :func:`~radial_ibvs_agents.experiments.reproduce.reproduce` records), the feature errors
    ``c*_ij - c_ij`` (Fig. 6) and the ``alpha_m`` error (Fig. 8, degrees). Bottom: the IBVS
    camera velocity (m/s, rad/s) and the robot's command (Fig. 7, fractions of the speed
    limits), and the path (metres). The signals are :func:`servoing_signals`'.

    Parameters
    ----------
    log
        The episode (its ``extra["goal_depths"]`` holds the goal depths the policy used).
    path
        Output image; ``None`` saves nothing (the figure stays open, e.g. to show inline).
    lam
        The IBVS gain used, 1/s (for the camera velocity).
    axes
        A ``(2, 3)`` grid of matplotlib ``Axes`` to draw into (``plt.subplots(2, 3)``); the
        figure's title and layout are then left to the caller. Default: a new ``14 x 7`` inch
        figure, titled with the policy, scenario, goal yaw and physics.

    Returns
    -------
    pathlib.Path or None
        ``path``, or ``None`` when nothing was saved.

    Raises
    ------
    ValueError
        If ``axes`` is not a 2 x 3 grid, or the log has no goal depths
        (:func:`servoing_signals`).
    """
    if axes is not None and np.shape(np.asarray(axes, dtype=object)) != (2, 3):
        raise ValueError(f"axes must be a (2, 3) grid of Axes, got shape {np.shape(axes)}")
    s = servoing_signals(log, lam)
    if axes is None:
        fig, grid = pyplot().subplots(2, 3, figsize=(14, 7))
    else:
        grid = np.asarray(axes, dtype=object)
        fig = grid[0, 0].figure
    k = np.arange(len(log.poses))
    ax = grid[0, 0]
    for p in range(s["pixel_error"].shape[1]):
        ax.plot(k, s["pixel_error"][:, p, 0], color=f"C{p % 10}", lw=1)
        ax.plot(k, s["pixel_error"][:, p, 1], color=f"C{p % 10}", lw=1, ls="--")
    ax.set_title("image point errors u - u*, v - v* (- -) [px]")
    grid[0, 1].plot(k, s["c_error"], lw=0.8)
    grid[0, 1].set_title("feature errors c*_ij - c_ij")
    grid[0, 2].plot(k, np.degrees(s["alpha_m_error"]), color="C3")
    grid[0, 2].set_title("alpha_m error alpha*_m - alpha_m [deg]")
    for column, label in enumerate(("v_x [m/s]", "v_y [m/s]", "omega_z [rad/s]")):
        grid[1, 0].plot(k, s["camera_velocity"][:, column], label=label)
    grid[1, 0].set_title("camera velocity (IBVS, current frame)")
    grid[1, 0].legend(fontsize=8)
    grid[1, 1].plot(k[1:], s["robot_velocity"][:, 0], label="v / v_max")
    grid[1, 1].plot(k[1:], s["robot_velocity"][:, 1], label="omega / omega_max")
    grid[1, 1].set_title("robot velocity command (eq. 38)")
    grid[1, 1].legend(fontsize=8)
    grid[1, 2].plot(*log.poses[:, :2].T, color="C0")
    grid[1, 2].plot(*log.info["goal_pose"][:2], "ks")
    grid[1, 2].set_aspect("equal")
    grid[1, 2].set_title("path [m]")
    for ax in grid.flat[:5]:
        ax.set_xlabel("iteration")
        ax.grid(alpha=0.3)
    if axes is None:
        yaw = round(float(np.degrees(log.info["goal_pose"][2]))) % 360
        fig.suptitle(f"{log.policy}, {log.scenario}, goal yaw {yaw} deg, {log.physics}")
        fig.tight_layout()
    return _save(fig, path, close=axes is None)
