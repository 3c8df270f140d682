"""Planar robot poses and the camera frame of a robot moving on the floor."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from radial_ibvs_gym._validation import as_float_array, check_finite, check_last_dim

__all__ = ["world_to_camera"]


def world_to_camera(
    points_world: ArrayLike, pose: ArrayLike, camera_height: float, *, validate: bool = True
) -> NDArray[np.float64]:
    """Express world points in the camera frame of a robot at a planar pose.

    The camera sits on the robot's rotation axis, ``camera_height`` metres above the floor,
    with its z axis (the mirror axis) pointing up, x along the robot's heading and y to its
    left. This is the frame of eq. (9) and of every interaction matrix.

    Parameters
    ----------
    points_world
        ``(..., N, 3)`` points in the world frame (metres; z up, floor at z = 0).
    pose
        ``(..., 3)`` robot poses ``(x, y, yaw)`` in metres and radians.
    camera_height
        Height of the camera's optical centre above the floor, metres.
    validate
        Check shapes and finiteness (``False`` skips it on hot paths that guarantee them).

    Returns
    -------
    numpy.ndarray
        ``(..., N, 3)`` points in the camera frame, metres.
    """
    p = as_float_array(points_world, "points_world")
    q = as_float_array(pose, "pose")
    if validate:
        check_last_dim(p, 3, "points_world")
        check_last_dim(q, 3, "pose")
        check_finite(p, "points_world")
        check_finite(q, "pose")
    c: float | NDArray[np.float64]
    s: float | NDArray[np.float64]
    if q.ndim == 1:  # one pose: scalar trigonometry (the environments' hot path)
        x, y, yaw = q.tolist()
        c, s = math.cos(yaw), math.sin(yaw)
        dx, dy = p[..., 0] - x, p[..., 1] - y
    else:
        dx = p[..., 0] - q[..., None, 0]
        dy = p[..., 1] - q[..., None, 1]
        c, s = np.cos(q[..., None, 2]), np.sin(q[..., None, 2])
    z = np.broadcast_to(p[..., 2] - camera_height, np.shape(dx))  # poses may add batch axes
    return np.stack([c * dx + s * dy, -s * dx + c * dy, z], axis=-1)
