"""What several diagnostics share: the goal's pose solved from one image pair, numpy in and out.

The diagnostics run as scripts (``python research/diagnostics/NAME.py``), so this folder is on
their ``sys.path`` and they import this module as ``_common``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from agents.learned.pose_layer import solve_goal_pose

__all__ = ["solve_one"]


def solve_one(
    points: Any, visible: Any, goal_points: Any, goal_visible: Any, depths: Any
) -> tuple[np.ndarray, bool]:
    """:func:`~agents.learned.pose_layer.solve_goal_pose` for one image pair, numpy in and out.

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
