"""Rotations, the SE(3) exponential and rigid motions of point sets (batched numpy).

Conventions: rotation matrices act on column vectors, point sets are rows ``(..., N, 3)``.
A camera twist ``xi = (v, omega)`` (metres/second, radians/second) is expressed in the camera
frame; a static point then moves in that frame as ``dP/dt = -v - omega x P``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from radial_ibvs_gym._validation import as_float_array, check_last_dim

__all__ = [
    "apply_twist_to_points",
    "rot2",
    "rot_x",
    "rot_y",
    "rot_z",
    "se3_exp",
    "skew",
    "so3_exp",
]


def rot2(angle: ArrayLike) -> NDArray[np.float64]:
    """2D rotation matrices, shape ``(..., 2, 2)``, for angles in radians of shape ``(...)``."""
    a = np.asarray(angle, dtype=np.float64)
    c, s = np.cos(a), np.sin(a)
    return np.stack([np.stack([c, -s], -1), np.stack([s, c], -1)], -2)


def _rot(angle: ArrayLike, axis: int) -> NDArray[np.float64]:
    a = np.asarray(angle, dtype=np.float64)
    c, s = np.cos(a), np.sin(a)
    out = np.zeros((*a.shape, 3, 3))
    i, j = [k for k in range(3) if k != axis]
    out[..., axis, axis] = 1.0
    out[..., i, i] = c
    out[..., j, j] = c
    out[..., i, j] = -s
    out[..., j, i] = s
    return out


def rot_x(angle: ArrayLike) -> NDArray[np.float64]:
    """Rotation about x by ``angle`` radians, shape ``(..., 3, 3)``."""
    return _rot(angle, 0)


def rot_y(angle: ArrayLike) -> NDArray[np.float64]:
    """Rotation about y by ``angle`` radians, shape ``(..., 3, 3)``."""
    # _rot's (i, j) = (0, 2) ordering gives the transpose of the right-handed rotation about y.
    return np.swapaxes(_rot(angle, 1), -1, -2)


def rot_z(angle: ArrayLike) -> NDArray[np.float64]:
    """Rotation about z by ``angle`` radians, shape ``(..., 3, 3)``."""
    return _rot(angle, 2)


def skew(w: ArrayLike) -> NDArray[np.float64]:
    """Skew-symmetric matrices ``[w]_x`` with ``[w]_x p = w x p``; ``(..., 3) -> (..., 3, 3)``."""
    w = as_float_array(w, "w")
    check_last_dim(w, 3, "w")
    z = np.zeros(w.shape[:-1])
    wx, wy, wz = w[..., 0], w[..., 1], w[..., 2]
    return np.stack(
        [np.stack([z, -wz, wy], -1), np.stack([wz, z, -wx], -1), np.stack([-wy, wx, z], -1)], -2
    )


def so3_exp(w: ArrayLike) -> NDArray[np.float64]:
    """Rodrigues' formula: rotation matrices ``exp([w]_x)``, ``(..., 3) -> (..., 3, 3)``.

    ``w`` is a rotation vector in radians. Small angles use the Taylor series, so the result
    is accurate to machine precision for every angle.
    """
    w = as_float_array(w, "w")
    check_last_dim(w, 3, "w")
    theta2 = np.sum(w * w, axis=-1)
    theta = np.sqrt(theta2)
    small = theta < 1e-4
    safe = np.where(small, 1.0, theta)
    a = np.where(small, 1.0 - theta2 / 6.0 + theta2**2 / 120.0, np.sin(safe) / safe)
    b = np.where(small, 0.5 - theta2 / 24.0 + theta2**2 / 720.0, (1.0 - np.cos(safe)) / safe**2)
    k = skew(w)
    eye = np.broadcast_to(np.eye(3), k.shape)
    return eye + a[..., None, None] * k + b[..., None, None] * (k @ k)


def se3_exp(twist: ArrayLike) -> NDArray[np.float64]:
    """Exponential of a twist ``(v, omega)``: homogeneous transforms, ``(..., 6) -> (..., 4, 4)``.

    Parameters
    ----------
    twist
        ``(..., 6)``: linear part ``v`` (metres) then angular part ``omega`` (radians),
        i.e. a velocity integrated over unit time.

    Returns
    -------
    numpy.ndarray
        ``(..., 4, 4)`` transforms ``T = [[R, V v], [0, 1]]`` with ``R = exp([omega]_x)``.
    """
    twist = as_float_array(twist, "twist")
    check_last_dim(twist, 6, "twist")
    v, w = twist[..., :3], twist[..., 3:]
    theta2 = np.sum(w * w, axis=-1)
    theta = np.sqrt(theta2)
    small = theta < 1e-4
    safe = np.where(small, 1.0, theta)
    b = np.where(small, 0.5 - theta2 / 24.0 + theta2**2 / 720.0, (1.0 - np.cos(safe)) / safe**2)
    c = np.where(
        small, 1.0 / 6.0 - theta2 / 120.0 + theta2**2 / 5040.0, (safe - np.sin(safe)) / safe**3
    )
    k = skew(w)
    eye = np.broadcast_to(np.eye(3), k.shape)
    V = eye + b[..., None, None] * k + c[..., None, None] * (k @ k)
    out = np.zeros((*twist.shape[:-1], 4, 4))
    out[..., :3, :3] = so3_exp(w)
    out[..., :3, 3] = np.einsum("...ij,...j->...i", V, v)
    out[..., 3, 3] = 1.0
    return out


def apply_twist_to_points(points: ArrayLike, twist: ArrayLike, dt: float) -> NDArray[np.float64]:
    """Coordinates of static points after the camera moves with ``twist`` for ``dt`` seconds.

    The camera pose becomes ``T = se3_exp(dt * twist)`` relative to the old one, so a static
    point ``P`` (old camera frame) has new coordinates ``T^-1 P``. At ``dt -> 0`` this gives
    ``dP/dt = -v - omega x P``, the convention of every interaction matrix in this package.

    Parameters
    ----------
    points
        ``(..., N, 3)`` points in the camera frame (metres).
    twist
        ``(..., 6)`` camera twist ``(v, omega)`` in the camera frame (m/s, rad/s).
    dt
        Duration in seconds (may be negative).

    Returns
    -------
    numpy.ndarray
        ``(..., N, 3)`` points in the moved camera frame.
    """
    p = as_float_array(points, "points")
    check_last_dim(p, 3, "points")
    T = se3_exp(dt * as_float_array(twist, "twist"))
    R, t = T[..., :3, :3], T[..., :3, 3]
    # T^-1 P = R^T (P - t); rows: (P - t) @ R
    return np.einsum("...nj,...jk->...nk", p - t[..., None, :], R)
