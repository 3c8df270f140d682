"""Planar robot poses and the camera frame of a robot moving on the floor."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from radial_ibvs_gym._validation import as_float_array, check_finite, check_last_dim
from radial_ibvs_gym.geometry.angles import wrap_angle, wrap_angle_scalar

__all__ = ["pose_in_frame", "relative_pose", "world_to_camera"]


def world_to_camera(
    points_world: ArrayLike,
    pose: ArrayLike,
    camera_height: float | NDArray[np.float64],
    *,
    validate: bool = True,
) -> NDArray[np.float64]:
    """Express world points in the camera frame of a robot at a planar pose.

    The camera sits on the robot's rotation axis, ``camera_height`` metres above the floor,
    with its z axis (the mirror axis) pointing up, x along the robot's heading and y to its
    left. This is the frame of eq. (9) and of every interaction matrix. One pose or a batch,
    each pose's points are the same bits: the yaw's cosine and sine come from ``math`` (the C
    library) in both cases, not from numpy's SIMD loops, whose last bit may differ by CPU.

    Parameters
    ----------
    points_world
        ``(..., N, 3)`` points in the world frame (metres; z up, floor at z = 0).
    pose
        ``(..., 3)`` robot poses ``(x, y, yaw)`` in metres and radians.
    camera_height
        Height of the camera's optical centre above the floor, metres: one, or an array that
        broadcasts against ``(..., N)`` (e.g. ``(B, 1)``, one per pose of a batch).
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
    else:  # the same libm trigonometry as one pose: a batch gives each pose's bits
        dx = p[..., 0] - q[..., None, 0]
        dy = p[..., 1] - q[..., None, 1]
        yaw = q[..., 2:3]
        angles = yaw.ravel().tolist()
        c = np.array([math.cos(a) for a in angles]).reshape(yaw.shape)
        s = np.array([math.sin(a) for a in angles]).reshape(yaw.shape)
    z = np.broadcast_to(p[..., 2] - camera_height, np.shape(dx))  # poses may add batch axes
    return np.stack([c * dx + s * dy, -s * dx + c * dy, z], axis=-1)


def relative_pose(frame: ArrayLike, pose: ArrayLike) -> NDArray[np.float64]:
    """Express planar poses in the frame of other planar poses.

    Parameters
    ----------
    frame
        ``(..., 3)`` poses ``(x, y, yaw)`` defining the frames, world frame, metres and radians.
    pose
        ``(..., 3)`` poses to express, world frame (broadcast against ``frame``).

    Returns
    -------
    numpy.ndarray
        ``(..., 3)``: ``pose``'s position in ``frame`` (x forward, y left; metres) and its yaw
        minus ``frame``'s, wrapped to ``[-pi, pi)`` (radians).

    Raises
    ------
    ValueError
        For shapes other than ``(..., 3)`` or NaN/inf.
    """
    f = as_float_array(frame, "frame")
    p = as_float_array(pose, "pose")
    for array, name in ((f, "frame"), (p, "pose")):
        check_last_dim(array, 3, name)
        check_finite(array, name)
    dx, dy = p[..., 0] - f[..., 0], p[..., 1] - f[..., 1]
    c, s = np.cos(f[..., 2]), np.sin(f[..., 2])
    yaw = wrap_angle(p[..., 2] - f[..., 2])
    return np.stack(np.broadcast_arrays(c * dx + s * dy, -s * dx + c * dy, yaw), axis=-1)


def pose_in_frame(frame: Any, pose: Any) -> tuple[float, float, float]:
    """Express one planar pose in the frame of another: :func:`relative_pose` for one pair.

    Scalar trigonometry (``math``), for the policies' per-step hot paths; the same formula as
    :func:`relative_pose`, without its validation.

    Parameters
    ----------
    frame, pose
        ``(3,)`` poses ``(x, y, yaw)``, world frame, metres and radians.

    Returns
    -------
    tuple of float
        ``pose``'s position in ``frame`` (x along ``frame``'s heading, y to its left; metres)
        and its yaw minus ``frame``'s, wrapped to ``[-pi, pi)`` (radians).
    """
    fx, fy, fyaw = (float(v) for v in frame[:3])
    px, py, pyaw = (float(v) for v in pose[:3])
    dx, dy = px - fx, py - fy
    c, s = math.cos(fyaw), math.sin(fyaw)
    return c * dx + s * dy, -s * dx + c * dy, wrap_angle_scalar(pyaw - fyaw)
