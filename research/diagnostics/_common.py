"""What several diagnostics share: the goal's pose from one image pair; the imperfect cameras.

The diagnostics run as scripts (``python research/diagnostics/NAME.py``), so this folder is on
their ``sys.path`` and they import this module as ``_common``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from radial_ibvs_agents.experiments.suites import SUITES
from radial_ibvs_agents.learned.networks.pose_layer import solve_goal_pose

__all__ = ["imperfect_cameras", "solve_one"]


def solve_one(
    points: Any, visible: Any, goal_points: Any, goal_visible: Any, depths: Any
) -> tuple[np.ndarray, bool]:
    """:func:`~radial_ibvs_agents.learned.networks.pose_layer.solve_goal_pose` for one image pair,
    numpy in and out.

    Parameters
    ----------
    points, goal_points
        ``(N, 2)`` (or flattened ``(2N,)``) current and goal image points.
    visible, goal_visible
        ``(N,)`` whether each landmark is seen now and in the goal image (truthy values; an
        observation's ``goal_visible`` is ``|x_n*| > 0.5``, hidden slots being zeros).
    depths
        ``(N,)`` goal depths ``d*``, metres, in the same order as the points.

    Returns
    -------
    pose : numpy.ndarray
        ``(4,)`` float64 ``(t_x, t_y, cos theta, sin theta)`` (zeros where not valid).
    valid : bool
    """
    import torch

    now = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    goal = np.asarray(goal_points, dtype=np.float64).reshape(-1, 2)
    n = len(now)
    seen = (np.asarray(visible, dtype=np.float64).reshape(-1)[:n] > 0.5) & (
        np.asarray(goal_visible, dtype=np.float64).reshape(-1)[:n] > 0.5
    )
    pose, valid = solve_goal_pose(
        torch.from_numpy(now)[None],
        torch.from_numpy(goal[:n])[None],
        torch.from_numpy(np.asarray(depths, dtype=np.float64).reshape(-1)[:n].copy())[None],
        torch.from_numpy(seen.astype(np.float64))[None],
    )
    return pose[0].numpy(), bool(valid[0])


def imperfect_cameras(
    labels: list[str] | tuple[str, ...] | None = None,
) -> dict[str, dict[str, Any]]:
    """Return the ``imperfect`` suite's ``gym.make`` arguments by variant label (scenario too).

    ``"ideal"`` names the same rooms through the ideal camera; ``labels=None``: every variant,
    ``"ideal"`` last. For the diagnostics that run their own policies through the suite's
    cameras (``teacher_through_camera.py``, ``goal_image_limit.py``).

    Raises
    ------
    ValueError
        For an unknown label (the message lists the valid ones).
    """
    table = {v.label: {"scenario": v.scenario, **v.overrides} for v in SUITES["imperfect"]}
    first = next(iter(table.values()))
    camera = {k: v for k, v in first["camera"].items() if k != "imperfections"}
    table["ideal"] = {**first, "camera": camera}
    if labels is None:
        return table
    unknown = [label for label in labels if label not in table]
    if unknown:
        raise ValueError(f"unknown imperfect variant(s) {unknown}; valid: {list(table)}")
    return {label: table[label] for label in labels}
