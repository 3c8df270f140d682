"""Figures in the style of the paper's Fig. 3-4 (paths) and Fig. 6-8 (servoing signals)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from agents import IBVSPolicy
from agents.plotting import pyplot, save_figure
from agents.runner import EpisodeLog
from radial_ibvs_gym.features import alpha_m, c_ij, virtual_point_weights
from radial_ibvs_gym.geometry import wrap_angle

__all__ = ["plot_paths", "plot_servoing", "servoing_signals"]

_STYLE = {"ibvs": ("C0", "-"), "oracle": ("k", "--"), "ibvs-d1.3": ("C3", "-.")}


def plot_paths(
    logs: Sequence[EpisodeLog], compare: Sequence[str], path: Path | str, title: str
) -> Path:
    """Paths of the given cases, one panel per goal yaw (Fig. 3: IBVS vs oracle; Fig. 4: d*).

    Parameters
    ----------
    logs
        Episodes of one backend (their ``policy`` labels name the cases).
    compare
        The case labels to draw, e.g. ``("ibvs", "oracle")``.
    path
        Output image.
    title
        Figure title.
    """
    plt = pyplot()
    tasks = sorted({log.task for log in logs if log.task is not None})
    fig, axes = plt.subplots(1, len(tasks), figsize=(3.6 * len(tasks), 3.8), squeeze=False)
    for ax, task in zip(axes[0], tasks, strict=True):
        for log in logs:
            if log.task != task or log.policy not in compare:
                continue
            color, style = _STYLE.get(log.policy, ("C2", ":"))
            ax.plot(*log.poses[:, :2].T, style, color=color, label=log.policy, lw=1.6)
            for pose, marker in ((log.poses[0], "o"), (log.info["goal_pose"], "s")):
                ax.plot(*pose[:2], marker, color="0.3", ms=5)
                ax.arrow(*pose[:2], 0.5 * np.cos(pose[2]), 0.5 * np.sin(pose[2]), width=0.02)
        yaw = round(float(np.degrees(_goal_yaw(logs, task))))
        ax.set_title(f"goal yaw {yaw % 360} deg")
        ax.set_aspect("equal")
        ax.set_xlabel("x [m]")
        ax.grid(alpha=0.3)
    axes[0, 0].set_ylabel("y [m]")
    axes[0, 0].legend(loc="upper left", fontsize=8)
    fig.suptitle(title)
    fig.tight_layout()
    return save_figure(fig, path)


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


def plot_servoing(log: EpisodeLog, path: Path | str, lam: float = 0.5) -> Path:
    """Fig. 6-8 for one episode: image, feature and ``alpha_m`` errors; camera and robot speeds."""
    plt = pyplot()
    s = servoing_signals(log, lam)
    k = np.arange(len(log.poses))
    fig, axes = plt.subplots(2, 3, figsize=(14, 7))
    ax = axes[0, 0]
    for p in range(s["pixel_error"].shape[1]):
        ax.plot(k, s["pixel_error"][:, p, 0], color=f"C{p % 10}", lw=1)
        ax.plot(k, s["pixel_error"][:, p, 1], color=f"C{p % 10}", lw=1, ls="--")
    ax.set_title("image point errors u - u*, v - v* (- -) [px]")
    axes[0, 1].plot(k, s["c_error"], lw=0.8)
    axes[0, 1].set_title("feature errors c*_ij - c_ij")
    axes[0, 2].plot(k, np.degrees(s["alpha_m_error"]), color="C3")
    axes[0, 2].set_title("alpha_m error alpha*_m - alpha_m [deg]")
    for column, label in enumerate(("v_x [m/s]", "v_y [m/s]", "omega_z [rad/s]")):
        axes[1, 0].plot(k, s["camera_velocity"][:, column], label=label)
    axes[1, 0].set_title("camera velocity (IBVS, current frame)")
    axes[1, 0].legend(fontsize=8)
    axes[1, 1].plot(k[1:], s["robot_velocity"][:, 0], label="v / v_max")
    axes[1, 1].plot(k[1:], s["robot_velocity"][:, 1], label="omega / omega_max")
    axes[1, 1].set_title("robot velocity command (eq. 38)")
    axes[1, 1].legend(fontsize=8)
    axes[1, 2].plot(*log.poses[:, :2].T, color="C0")
    axes[1, 2].plot(*log.info["goal_pose"][:2], "ks")
    axes[1, 2].set_aspect("equal")
    axes[1, 2].set_title("path [m]")
    for ax in axes.flat[:5]:
        ax.set_xlabel("iteration")
        ax.grid(alpha=0.3)
    yaw = round(float(np.degrees(log.info["goal_pose"][2]))) % 360
    fig.suptitle(f"{log.policy}, {log.scenario}, goal yaw {yaw} deg, {log.physics}")
    fig.tight_layout()
    return save_figure(fig, path)
