"""Small helpers for the control notebooks (``notebooks/03_*`` and ``notebooks/04_*``).

The notebooks import and call these; they hold no library logic of their own. Four groups:

- what the IBVS estimates, and the truth to compare it with: :func:`goal_in_robot_frame`
  (the virtual target of eq. 38 from the true poses), :func:`ideal_observation` (the env's
  observation of an ideal camera, eq. 9, at any pose) and :func:`ibvs_estimates` (the target
  the paper's IBVS estimates from it, eq. 30 and 36-37);
- running and measuring episodes: :func:`run_task`, :func:`hausdorff_distance`,
  :func:`starts_in_goal_frame` (the domain of convergence);
- training: :func:`small_train_config` (a config shrunk to a few hundred or thousand steps),
  :func:`read_progress_csv` (stable-baselines3's log);
- drawing on given matplotlib ``Axes`` (matplotlib itself is imported lazily, only by
  :func:`preserve_matplotlib_backend`): :func:`draw_pose` and the library's
  :func:`draw_convergence_map`. The paper's figures are the library's, drawn into the
  notebook's axes: :func:`radial_ibvs_agents.experiments.figures.plot_paths` (Fig. 3-4) and
  :func:`radial_ibvs_agents.experiments.figures.plot_servoing` (Fig. 6-8), both with ``axes=``.

Conventions as everywhere in the package (``docs/conventions.md``): robot poses ``(x, y, yaw)``
in the world frame, metres and radians, yaw counter-clockwise from the world x axis; the robot
frame has x forward and y to the left; actions are normalised to ``[-1, 1]``
(``(v / v_max, omega / omega_max)``).
"""

from __future__ import annotations

import csv
import dataclasses
import math
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

import radial_ibvs_gym  # noqa: F401  (registers the environments)
from radial_ibvs_agents.analytic.ibvs_policy import IBVSPolicy
from radial_ibvs_agents.experiments.benchmark_plots import (
    draw_convergence_map,
    starts_in_goal_frame,
)
from radial_ibvs_agents.learned.training.zoo_config import TrainConfig
from radial_ibvs_agents.rollouts import EpisodeLog, make_env, run_episode
from radial_ibvs_gym._validation import as_float_array
from radial_ibvs_gym.camera import radial_points
from radial_ibvs_gym.geometry import relative_pose, world_to_camera

if TYPE_CHECKING:
    from matplotlib.axes import Axes

__all__ = [
    "draw_convergence_map",
    "draw_pose",
    "goal_in_robot_frame",
    "hausdorff_distance",
    "ibvs_estimates",
    "ideal_observation",
    "preserve_matplotlib_backend",
    "read_progress_csv",
    "run_task",
    "small_train_config",
    "starts_in_goal_frame",
]


# --- what the IBVS estimates, and the truth -------------------------------------------------


def goal_in_robot_frame(robot_pose: ArrayLike, goal_pose: ArrayLike) -> NDArray[np.float64]:
    """Express the goal pose in the robot frame: the virtual target of the smooth control law.

    Parameters
    ----------
    robot_pose, goal_pose
        ``(..., 3)`` poses ``(x, y, yaw)`` in the world frame, metres and radians
        (broadcast against each other).

    Returns
    -------
    numpy.ndarray
        ``(..., 3)``: the goal position ``(x, y)`` in the robot frame (metres; x forward,
        y to the left) and the rotation from the robot's heading to the goal's,
        ``wrap(yaw_goal - yaw_robot)`` in ``[-pi, pi)`` (radians). The paper's IBVS estimates
        the first two as ``v / lambda`` and the third as ``gamma`` (eq. 37).

    Raises
    ------
    ValueError
        For shapes other than ``(..., 3)`` or NaN/inf.
    """
    return relative_pose(robot_pose, goal_pose)


def ideal_observation(
    landmarks: ArrayLike,
    robot_pose: ArrayLike,
    goal_pose: ArrayLike,
    camera_height: float,
    depth_scale: float = 1.0,
) -> dict[str, NDArray[np.float32]]:
    """Build what ``Parking-v0`` (``goal_depths=True``) observes with an ideal camera at a pose.

    Every landmark is taken as visible (true for the paper's eight points along the parking
    paths of ``paper-sim``); the image points are the radial model of eq. (9), ``x_n`` the
    unit bearing of each landmark in the camera frame.

    Parameters
    ----------
    landmarks
        ``(N, 3)`` landmark positions, world frame, metres.
    robot_pose, goal_pose
        ``(3,)`` poses ``(x, y, yaw)``, metres and radians.
    camera_height
        Height of the camera above the floor, metres.
    depth_scale
        Scale error on the goal depths ``d*`` (the paper's second simulation: 1.3).

    Returns
    -------
    dict
        ``points`` and ``goal_points`` ``(2N,)`` (flattened ``x_n`` and ``x_n*``),
        ``visible`` ``(N,)`` (ones) and ``goal_depths`` ``(N,)`` (metres), float32 as in the
        env.

    Raises
    ------
    ValueError
        For bad shapes, NaN/inf, a non-positive depth scale or a landmark on the camera axis.
    """
    if not (math.isfinite(depth_scale) and depth_scale > 0):
        raise ValueError(f"depth_scale must be finite and positive, got {depth_scale!r}")
    now = radial_points(world_to_camera(landmarks, robot_pose, camera_height))
    goal = radial_points(world_to_camera(landmarks, goal_pose, camera_height))
    return {
        "points": now.x_n.reshape(-1).astype(np.float32),
        "goal_points": goal.x_n.reshape(-1).astype(np.float32),
        "visible": np.ones(len(goal.d), dtype=np.float32),
        "goal_depths": (depth_scale * goal.d).astype(np.float32),
    }


def ibvs_estimates(
    policy: IBVSPolicy,
    landmarks: ArrayLike,
    robot_poses: ArrayLike,
    goal_pose: ArrayLike,
    camera_height: float,
    depth_scale: float = 1.0,
) -> NDArray[np.float64]:
    """Estimate the virtual target with the paper's IBVS at each of a set of robot poses.

    Parameters
    ----------
    policy
        An :class:`~radial_ibvs_agents.analytic.ibvs_policy.IBVSPolicy` (variant ``paper`` or
        ``no-frame-change``: the ones that need only the goal depths).
    landmarks
        ``(N, 3)`` landmark positions, world frame, metres.
    robot_poses
        ``(K, 3)`` robot poses ``(x, y, yaw)``, metres and radians.
    goal_pose
        ``(3,)`` goal pose.
    camera_height
        Height of the camera above the floor, metres.
    depth_scale
        Scale error on the goal depths ``d*``.

    Returns
    -------
    numpy.ndarray
        ``(K, 3)`` rows ``(v_x / lambda, v_y / lambda, gamma)``: the estimated goal position in
        the robot frame (metres) and rotation to the goal heading (radians), to compare with
        :func:`goal_in_robot_frame`; NaN where the IBVS has no estimate.
    """
    poses = as_float_array(robot_poses, "robot_poses").reshape(-1, 3)
    out = np.full((len(poses), 3), np.nan)
    for k, pose in enumerate(poses):
        obs = ideal_observation(landmarks, pose, goal_pose, camera_height, depth_scale)
        estimate = policy.twist(obs)
        if estimate is not None:
            v, gamma = estimate
            out[k] = (v[0] / policy.lam, v[1] / policy.lam, gamma)
    return out


# --- running and measuring episodes ---------------------------------------------------------


def run_task(
    policy: Any,
    task: int | None = None,
    *,
    scenario: str = "paper-sim",
    physics: str = "kinematic",
    seed: int = 0,
    options: Mapping[str, Any] | None = None,
    policy_name: str | None = None,
    max_steps: int | None = None,
    env_id: str = "RadialIBVS/Parking-v0",
    **env_kwargs: Any,
) -> EpisodeLog:
    """Make the env a policy needs, run one episode, close the env.

    Parameters
    ----------
    policy
        Anything with stable-baselines3's ``predict`` and an ``env_kwargs`` mapping (every
        policy of :mod:`radial_ibvs_agents`).
    task
        Task index (``paper-sim``: 0..3, goal yaw 0, 90, 180, 270 deg); ``None`` lets the
        seed draw one.
    scenario, physics
        ``gym.make`` arguments.
    seed
        Reset seed.
    options
        Reset options (``start``, ``goal``: poses ``(x, y, yaw)``, metres and radians).
    policy_name
        Name recorded in the log (default: the policy's class name).
    max_steps
        Extra step budget on top of the env's truncation (600 steps of 0.1 s).
    env_id
        The Gymnasium id.
    **env_kwargs
        Further ``gym.make`` arguments (``depth_scale=1.3``, ``success_position_m``, ...).

    Returns
    -------
    EpisodeLog
        The episode; ``extra["goal_depths"]`` holds the goal depths ``d*`` given to the
        policy (metres, scaled) when the env reports them, as
        :func:`~radial_ibvs_agents.experiments.figures.servoing_signals` needs.
    """
    overrides = {"physics": physics, **({"task": task} if task is not None else {})}
    env = make_env(policy, scenario, {**overrides, **env_kwargs}, env_id=env_id)
    try:
        log = run_episode(
            policy,
            env,
            seed=seed,
            options=dict(options) if options is not None else None,
            policy_name=policy_name,
            max_steps=max_steps,
        )
    finally:
        env.close()
    if "goal_depths" in log.info:
        log.extra["goal_depths"] = np.asarray(log.info["goal_depths"], dtype=np.float64)
    return log


def hausdorff_distance(path_a: ArrayLike, path_b: ArrayLike) -> float:
    """Hausdorff distance between two paths given as point sequences.

    Parameters
    ----------
    path_a, path_b
        ``(N, 2)`` and ``(M, 2)`` positions (more columns are ignored, e.g. the yaw of
        ``(x, y, yaw)`` poses), metres.

    Returns
    -------
    float
        The largest distance from a point of one path to the nearest point of the other,
        metres.

    Raises
    ------
    ValueError
        For an empty path or fewer than 2 columns.
    """
    a = as_float_array(path_a, "path_a")
    b = as_float_array(path_b, "path_b")
    for array, name in ((a, "path_a"), (b, "path_b")):
        if array.ndim != 2 or array.shape[1] < 2 or len(array) == 0:
            raise ValueError(f"{name} must be a non-empty (N, >=2) array, got {array.shape}")
    d = np.linalg.norm(a[:, None, :2] - b[None, :, :2], axis=-1)
    return float(max(d.min(axis=1).max(), d.min(axis=0).max()))


# --- training --------------------------------------------------------------------------------


def small_train_config(
    config: TrainConfig,
    *,
    n_envs: int,
    n_steps: int,
    batch_size: int | None = None,
    eval_freq: int,
    eval_episodes: int,
) -> TrainConfig:
    """Shrink a copy of a PPO training config for a short run (a notebook, a smoke test).

    PPO collects ``n_envs * n_steps`` env steps before each update, so a run shorter than that
    still collects a whole rollout: shrink both to train a few hundred steps.

    Parameters
    ----------
    config
        The config (:func:`radial_ibvs_agents.learned.training.zoo_config.load_train_config`).
    n_envs
        Parallel envs.
    n_steps
        Steps per env and rollout.
    batch_size
        Minibatch size (default: ``min(config's, n_envs * n_steps)``); must divide into the
        rollout for PPO not to warn.
    eval_freq
        Evaluate every this many env steps (all envs together).
    eval_episodes
        Held-out episodes per evaluation.

    Returns
    -------
    TrainConfig
        The shrunk copy (the original is unchanged).

    Raises
    ------
    ValueError
        For a non-positive count, a rollout of fewer than 2 steps, or a batch size that does
        not divide the rollout.
    """
    for name, value in (
        ("n_envs", n_envs),
        ("n_steps", n_steps),
        ("eval_freq", eval_freq),
        ("eval_episodes", eval_episodes),
    ):
        if int(value) != value or value <= 0:
            raise ValueError(f"{name} must be a positive integer, got {value!r}")
    rollout = n_envs * n_steps
    if rollout < 2:
        raise ValueError(f"n_envs * n_steps must be >= 2, got {rollout}")
    if batch_size is None:
        batch_size = min(int(config.algo_kwargs.get("batch_size", 64)), rollout)
    if batch_size <= 1 or rollout % batch_size:
        raise ValueError(f"batch_size must be > 1 and divide n_envs * n_steps = {rollout}")
    algo_kwargs = {**config.algo_kwargs, "n_steps": int(n_steps), "batch_size": int(batch_size)}
    return dataclasses.replace(
        config,
        n_envs=int(n_envs),
        algo_kwargs=algo_kwargs,
        eval_freq=int(eval_freq),
        eval_episodes=int(eval_episodes),
    )


def read_progress_csv(path: Path | str) -> dict[str, NDArray[np.float64]]:
    """Read stable-baselines3's ``progress.csv`` into one float array per column.

    Parameters
    ----------
    path
        The CSV (``logs/progress.csv`` of a training run, ``progress.csv`` of a shipped model).

    Returns
    -------
    dict
        Column name (e.g. ``time/total_timesteps``, ``rollout/ep_rew_mean``,
        ``rollout/success_rate``, ``eval/mean_reward``) -> ``(rows,)`` floats, NaN where a row
        has no value (evaluation columns are filled only on evaluation rows).

    Raises
    ------
    ValueError
        If the file is missing or has no header.
    """
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"{path} not found")
    with path.open(newline="") as handle:
        reader = csv.DictReader(handle)
        if not reader.fieldnames:
            raise ValueError(f"{path} has no header")
        columns: dict[str, list[float]] = {name: [] for name in reader.fieldnames}
        for row in reader:
            for name in columns:
                value = row.get(name) or ""
                try:
                    columns[name].append(float(value))
                except ValueError:
                    columns[name].append(math.nan)
    return {name: np.asarray(values, dtype=np.float64) for name, values in columns.items()}


# --- drawing ---------------------------------------------------------------------------------


@contextmanager
def preserve_matplotlib_backend() -> Iterator[None]:
    """Restore matplotlib's backend on exit.

    A guard around calls that may switch matplotlib's backend (third-party savers do; in
    Jupyter a switch to ``Agg`` stops later figures from showing inline). This package's own
    savers keep the current backend.
    """
    import matplotlib
    import matplotlib.pyplot as plt

    backend = matplotlib.get_backend()
    try:
        yield
    finally:
        if matplotlib.get_backend() != backend:
            plt.switch_backend(backend)


def draw_pose(
    ax: Axes, pose: ArrayLike, *, color: str = "0.3", marker: str = "o", length: float = 0.5
) -> None:
    """Draw a pose: a marker at the position and an arrow along the heading.

    Parameters
    ----------
    ax
        Matplotlib axes.
    pose
        ``(x, y, yaw)``, metres and radians.
    color, marker
        Matplotlib colour and marker.
    length
        Arrow length, metres.
    """
    x, y, yaw = (float(v) for v in np.asarray(pose, dtype=np.float64)[:3])
    ax.plot(x, y, marker, color=color, ms=5)
    ax.arrow(
        x, y, length * math.cos(yaw), length * math.sin(yaw), width=0.02, color=color, lw=0
    )  # fmt: skip
