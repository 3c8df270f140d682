"""The goal's planar pose solved from bearings in closed form (pure numpy, batched).

The constraints (``x_n`` a current bearing, ``p_n = d*_n x*_n`` the landmark in the goal's
frame, ``(R, t)`` the goal's pose in the robot's frame): ``q_n = R p_n + t`` lies along
``x_n``, so ``x_n x q_n = 0``, linear in ``z = (cos theta, sin theta, t_x, t_y)``; dividing
by ``d*_n`` weighs the landmarks alike. ``z`` is the eigenvector of the least eigenvalue of
the constraints' Gram matrix, scaled so that ``cos^2 + sin^2 = 1`` and signed so that the
landmarks lie in front of their bearings.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["solve_goal_pose"]


def solve_goal_pose(
    now: Any, goal: Any, depth: Any, mask: Any
) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Solve the goal's planar pose in the robot's frame from bearings (numpy, batched).

    Parameters
    ----------
    now, goal
        ``(..., N, 2)`` the landmarks' current and goal bearings (unit vectors: the
        normalised image points).
    depth
        ``(..., N)`` goal depths ``d*``, metres (horizontal distances at the goal).
    mask
        ``(..., N)`` true where the landmark is seen in both images.

    Returns
    -------
    pose : numpy.ndarray
        ``(..., 4)`` ``(t_x, t_y, cos theta, sin theta)``: the goal's position in the robot's
        frame (metres; x forward, y left) and its heading relative to the robot's (radians, as
        cosine and sine); zeros where not valid.
    valid : numpy.ndarray
        ``(...,)`` bool: at least three landmarks seen and a unique solution.
    """
    # written for few numpy operations (a robot's solve is mostly their fixed costs): each
    # slice taken once, the same arithmetic in the same order as the formulas above
    x = np.asarray(now, dtype=np.float64)
    g = np.asarray(goal, dtype=np.float64)
    d = np.maximum(np.asarray(depth, dtype=np.float64), 1e-3)
    w = np.asarray(mask, dtype=np.float64)
    x0, x1, g0, g1 = x[..., 0], x[..., 1], g[..., 0], g[..., 1]
    dot = x0 * g0
    dot += x1 * g1  # (x * g).sum(-1)
    rows = np.stack([x0 * g1 - x1 * g0, dot, -x1 / d, x0 / d], axis=-1)
    rows *= w[..., None]
    gram = np.swapaxes(rows, -1, -2) @ rows
    values, vectors = np.linalg.eigh(gram)
    z0, z1 = vectors[..., 0, 0], vectors[..., 1, 0]
    scale = np.sqrt(z0 * z0 + z1 * z1)  # numpy's norm of (z0, z1)
    z = vectors[..., 0] / np.maximum(scale, 1e-12)[..., None]
    c, s, tx, ty = z[..., 0:1], z[..., 1:2], z[..., 2:3], z[..., 3:4]
    p0, p1 = d * g0, d * g1
    qx = c * p0 - s * p1 + tx
    qy = s * p0 + c * p1 + ty
    front = ((x0 * qx + x1 * qy) * w).sum(axis=-1)
    z = np.where((front < 0)[..., None], -z, z)
    gap = values[..., 1] > 1e-9 * np.maximum(values[..., 3], 1e-30)
    valid = (w.sum(axis=-1) >= 3) & (scale > 1e-6) & gap & np.isfinite(z).all(axis=-1)
    return np.where(valid[..., None], z[..., [2, 3, 0, 1]], 0.0), valid
