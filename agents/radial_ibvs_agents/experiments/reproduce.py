"""``radial-ibvs reproduce paper-sim``: the paper's Section 4.1, as a table, data and figures.

Runs the four parking tasks with (a) the paper's IBVS, (b) the pose oracle (the same smooth
control law fed the true poses: the paper's "real 3D parameters") and (c) the IBVS with goal
depths scaled by 1.3, on each physics backend. Success here is the paper's accuracy: 1 cm and
0.5 deg (the envs' default is 2 cm / 2 deg).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np
from tqdm import tqdm  # text bars: no ipywidgets needed in Jupyter

from radial_ibvs_agents import make_policy
from radial_ibvs_agents.io import json_safe, write_csv
from radial_ibvs_agents.io import write_json as write_json_file
from radial_ibvs_agents.rollouts import make_env, run_episode
from radial_ibvs_agents.rollouts.log import EpisodeLog
from radial_ibvs_agents.rows import episode_row

__all__ = [
    "CASES",
    "ROBUSTNESS_CASES",
    "SUCCESS",
    "Case",
    "reproduce",
    "summary_table",
    "write_json",
    "write_trajectories_csv",
]

#: the paper's accuracy (Section 4.1 converges to a fraction of a centimetre and a degree)
SUCCESS = {"success_position_m": 0.01, "success_heading_deg": 0.5}


@dataclass(frozen=True)
class Case:
    """One configuration of the reproduction.

    Attributes
    ----------
    label
        Name in the table, the CSV and the JSON rows.
    policy
        Policy name (:func:`radial_ibvs_agents.make_policy`).
    depth_scale
        Scale error on the goal depths ``d*``.
    overrides
        Other scenario keys given to ``gym.make`` (camera, goal camera), as ``(key, value)``.
    """

    label: str
    policy: str
    depth_scale: float = 1.0
    overrides: tuple[tuple[str, Any], ...] = ()


CASES = (Case("ibvs", "ibvs"), Case("oracle", "oracle"), Case("ibvs-d1.3", "ibvs", 1.3))
_MIRROR_A = {"mirror": "A", "non_central_offset": 0.01}  # paper-sim's camera
#: the paper's robustness tests: goal image through mirror B, pixel noise, principal point error
ROBUSTNESS_CASES = (
    Case(
        "ibvs-goal-mirror-B",
        "ibvs",
        overrides=(("goal_camera", {"mirror": "B", "non_central_offset": 0.01}),),
    ),
    Case(
        "ibvs-noise-0.5px",
        "ibvs",
        overrides=(("camera", {**_MIRROR_A, "imperfections": {"pixel_noise_std": 0.5}}),),
    ),
    Case(
        "ibvs-pp-error-3px",
        "ibvs",
        overrides=(
            ("camera", {**_MIRROR_A, "imperfections": {"principal_point_offset": [3.0, -2.0]}}),
        ),
    ),
)


def reproduce(
    scenario: str = "paper-sim",
    physics: Sequence[str] = ("kinematic", "pymunk"),
    tasks: Iterable[int] | None = None,
    cases: Sequence[Case] = CASES,
    control_dt: float = 0.1,
    lam: float = 0.5,
    max_steps: int = 2000,
    progress: bool = True,
) -> list[EpisodeLog]:
    """Run every case on every task and backend.

    Parameters
    ----------
    scenario
        A scenario with tasks (``paper-sim``).
    physics
        Backends to run (``kinematic``, ``pymunk``).
    tasks
        Task indices (default: all of the scenario's).
    cases
        The configurations (default :data:`CASES`).
    control_dt
        Control period, seconds.
    lam
        The gain ``lambda`` of the IBVS and of the oracle's speed mapping, 1/s.
    max_steps
        Step budget per episode.
    progress
        Show a progress bar.

    Returns
    -------
    list of EpisodeLog
        One per (backend, task, case); ``extra`` holds ``depth_scale``, the pixel trajectory
        ``pixels`` ``(T + 1, N, 2)`` and the goal's ``goal_pixels`` ``(N, 2)`` (exact
        projection through the scenario's camera) and the goal depths.
    """
    runs: list[tuple[str, int, Case]] = []
    for backend in physics:
        for task in _tasks(scenario, tasks):
            runs.extend((backend, task, case) for case in cases)
    logs = []
    for backend, task, case in tqdm(runs, desc="reproduce", disable=not progress, unit="ep"):
        policy = make_policy(case.policy, lam=lam)
        overrides: dict[str, Any] = {
            "task": task,
            "physics": backend,
            "control_dt": control_dt,
            "depth_scale": case.depth_scale,
            **dict(case.overrides),
            **SUCCESS,
        }
        env = make_env(policy, scenario, overrides, max_episode_steps=max_steps)
        log = run_episode(policy, env, seed=0, policy_name=case.label)
        log.extra.update(_pixels(env, log))
        log.extra["depth_scale"] = case.depth_scale
        log.extra["goal_depths"] = np.asarray(log.info["goal_depths"], dtype=np.float64)
        logs.append(log)
        env.close()
    return logs


def _tasks(scenario: str, tasks: Iterable[int] | None) -> list[int]:
    from radial_ibvs_gym.scenarios import load_scenario

    n = load_scenario(scenario).n_tasks
    chosen = list(range(n)) if tasks is None else list(tasks)
    bad = [t for t in chosen if not 0 <= t < n]
    if bad:
        raise ValueError(f"task(s) {bad} out of range: scenario {scenario!r} has tasks 0..{n - 1}")
    return chosen


def _pixels(env: gym.Env, log: EpisodeLog) -> dict[str, np.ndarray]:
    """Pixel trajectories of the landmarks through the scenario's exact camera model."""
    from radial_ibvs_gym.geometry import world_to_camera

    base: Any = env.unwrapped
    scenario, landmarks = base.scenario, base.episode.landmarks
    h = base.episode.camera_height
    p_cam = world_to_camera(landmarks, log.poses, h)  # (T + 1, N, 3)
    pixels = scenario.camera.forward(p_cam).pixels
    goal = scenario.goal_camera.forward(world_to_camera(landmarks, base.episode.goal, h)).pixels
    return {"pixels": pixels, "goal_pixels": goal}


def summary_table(logs: Sequence[EpisodeLog]) -> str:
    """Format a Markdown table: one row per episode, the paper's quantities."""
    lines = [
        "| physics | goal yaw [deg] | case | success | position error [cm] | heading error [deg] "
        "| time [s] | path [m] |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for log in logs:
        yaw = round(float(np.degrees(log.info["goal_pose"][2]))) % 360
        lines.append(
            f"| {log.physics} | {yaw} | {log.policy} | {'yes' if log.success else 'no'} "
            f"| {100 * log.info['position_error_m']:.2f} | {log.info['heading_error_deg']:.3f} "
            f"| {log.steps * log.control_dt:.1f} | {log.path_length_m:.2f} |"
        )
    return "\n".join(lines) + "\n"


def write_trajectories_csv(logs: Sequence[EpisodeLog], path: Path | str) -> Path:
    """``trajectories.csv``: columns ``policy, task, physics, t, x, y, yaw`` (s, m, rad)."""
    rows = [
        [log.policy, log.task, log.physics, f"{t:.3f}", x, y, yaw]
        for log in logs
        for t, (x, y, yaw) in zip(log.times, log.poses, strict=True)
    ]
    return write_csv(path, rows, ["policy", "task", "physics", "t", "x", "y", "yaw"])


def write_json(logs: Sequence[EpisodeLog], path: Path | str) -> Path:
    """Write the ``--json`` rows: one object per episode (:meth:`EpisodeLog.row`)."""
    return write_json_file(path, [json_safe(episode_row(log)) for log in logs])
