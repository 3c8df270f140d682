"""The virtual point and its angle ``alpha_m`` for the camera rotation (eq. 22-29).

A fixed linear combination of the image points, ``p1 = sum_i a_i x_ni`` (eq. 22), defines a
direction ``v1 = p1 / |p1|`` (eq. 23) and an angle ``alpha_m = atan2(v1)`` (eq. 25) that
turns by exactly ``-gamma`` when the camera turns by ``gamma`` about its axis (``L_alpha_m`` has
``-1`` in its ``omega_z`` column). Unlike the mean of the point angles it has no wrap-around
discontinuity. The weights ``a`` are computed once from the goal image (eq. 27-29) so that the
virtual point of the goal image is a chosen unit vector ``p1*``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from radial_ibvs_gym._validation import as_float_array, check_finite, check_last_dim
from radial_ibvs_gym.features._checks import (
    UNIT_TOL,
    check_p1,
    check_points,
    check_scene,
    check_sign,
    check_weights,
)
from radial_ibvs_gym.features.points import _lxn

__all__ = ["L_alpha_m", "alpha_m", "virtual_point", "virtual_point_weights"]

#: ``B`` counts as rank-deficient when ``sigma_2 / sigma_1`` falls below this.
RANK_TOL = 1e-9


def virtual_point_weights(
    x_n_goal: ArrayLike, p1_star: ArrayLike = (1.0, 0.0)
) -> NDArray[np.float64]:
    """Weights ``a`` of the virtual point, from the goal image (eq. 27-29).

    ``V* = [p1*, p2*]`` with ``p2*`` equal to ``p1*`` turned by +90 degrees (a direct
    orthonormal basis), ``B = V*^T X*_nt`` (2 x N, the goal points' coordinates in that basis,
    eq. 27-28), and ``a`` is the first column of ``B^+`` (eq. 29; the paper's "first columns"
    means the first column). Since ``X*_nt = V* B`` and ``B B^+ = I`` when ``B`` has rank 2,
    ``X*_nt a = p1*``: the virtual point of the goal image is exactly ``p1*`` and
    ``alpha_m* = atan2(p1*)``. ``a`` is also the minimum-norm solution of ``X*_nt a = p1*``.
    (Eq. 27 writes ``v*_n1, v*_n2`` for ``p1*, p2*``.)

    Parameters
    ----------
    x_n_goal
        ``(..., N, 2)`` goal image points on the unit circle, ``N >= 2``, not all on one line
        through the principal point.
    p1_star
        ``(2,)`` or ``(..., 2)`` unit vector: the goal virtual point (the paper chooses it
        unitary). Default ``(1, 0)``, hence ``alpha_m* = 0``.

    Returns
    -------
    numpy.ndarray
        ``(..., N)`` dimensionless weights ``a``; compute them once per goal and keep them
        fixed while the camera moves.

    Raises
    ------
    ValueError
        For NaN/inf, points off the unit circle, fewer than 2 points, ``p1*`` not of unit
        norm, or a goal image whose points are all collinear with the optical axis
        (``x*_ni = +-u`` for one ``u``: ``B`` has rank < 2 and ``p1*`` is not a combination of
        the points).
    """
    x = check_points(x_n_goal, min_points=2, name="x_n_goal")
    p = as_float_array(p1_star, "p1_star")
    check_last_dim(p, 2, "p1_star")
    check_finite(p, "p1_star")
    norm = np.hypot(p[..., 0], p[..., 1])
    if np.any(np.abs(norm - 1.0) > UNIT_TOL):
        raise ValueError(f"p1_star must be a unit vector, got {p.tolist()} (norm {norm})")
    basis = np.stack([p, np.stack([-p[..., 1], p[..., 0]], axis=-1)], axis=-1)  # columns
    b = np.swapaxes(basis, -1, -2) @ np.swapaxes(x, -1, -2)  # (..., 2, N)
    sv = np.linalg.svd(b, compute_uv=False)
    ratio = sv[..., 1] / sv[..., 0]
    bad = ratio < RANK_TOL
    if np.any(bad):
        index = tuple(int(i) for i in np.argwhere(bad)[0])
        raise ValueError(
            f"goal image x_n_goal{list(index)} is degenerate: B = V*^T X*_nt has rank < 2 "
            f"(singular values {sv[index].tolist()}): all goal points are collinear with the "
            "optical axis (x*_n = +-u for one u), so p1* is no combination of them"
        )
    a: NDArray[np.float64] = np.asarray(np.linalg.pinv(b)[..., :, 0], dtype=np.float64)
    return a


def _p1(x: NDArray[np.float64], a: NDArray[np.float64]) -> NDArray[np.float64]:
    out: NDArray[np.float64] = np.sum(a[..., None] * x, axis=-2)
    return out


def virtual_point(x_n: ArrayLike, a: ArrayLike) -> NDArray[np.float64]:
    """Compute the virtual point ``p1 = sum_i a_i x_ni``, eq. (22).

    Parameters
    ----------
    x_n
        ``(..., N, 2)`` image points on the unit circle, ``N >= 2``.
    a
        ``(..., N)`` weights from :func:`virtual_point_weights`; leading dimensions broadcast
        with those of ``x_n`` (e.g. ``(N,)`` for one goal and a batch of scenes).

    Returns
    -------
    numpy.ndarray
        ``(..., 2)`` virtual points (dimensionless, not normalised; ``|p1|`` may be 0, which
        :func:`alpha_m` and :func:`L_alpha_m` reject).

    Raises
    ------
    ValueError
        For NaN/inf, points off the unit circle, fewer than 2 points, or ``a`` of the wrong
        shape.
    """
    x = check_points(x_n, min_points=2)
    return _p1(x, check_weights(a, x))


def alpha_m(x_n: ArrayLike, a: ArrayLike) -> NDArray[np.float64]:
    """Angle of the virtual point, eq. (23) and (25): ``alpha_m = atan2(v1_y, v1_x)``.

    Parameters
    ----------
    x_n
        ``(..., N, 2)`` image points on the unit circle, ``N >= 2``.
    a
        ``(..., N)`` weights from :func:`virtual_point_weights` (broadcast as in
        :func:`virtual_point`).

    Returns
    -------
    numpy.ndarray
        ``(...)`` angles in radians, in ``[-pi, pi]``. A camera rotation by ``gamma`` about its
        axis changes ``alpha_m`` by exactly ``-gamma`` (modulo ``2 pi``).

    Raises
    ------
    ValueError
        As :func:`virtual_point`, and when ``|p1| < 1e-9`` (no direction).
    """
    x = check_points(x_n, min_points=2)
    p = _p1(x, check_weights(a, x))
    check_p1(p)
    out: NDArray[np.float64] = np.arctan2(p[..., 1], p[..., 0])
    return out


def L_alpha_m(
    x_n: ArrayLike, d: ArrayLike, z_n: ArrayLike, a: ArrayLike, *, sign: int = 1
) -> NDArray[np.float64]:
    """Interaction matrix of ``alpha_m``, eq. (24) and (26).

    ``L_v1 = (I - v1 v1^T) / |p1| sum_i a_i L_xn_i`` (eq. 24) and
    ``L_alpha_m = v1_x L_v1,y - v1_y L_v1,x`` (eq. 26), i.e.
    ``L_alpha_m = v1_perp^T sum_i a_i L_xn_i / |p1|`` with ``v1_perp = (-v1_y, v1_x)``.
    Finite differences (with ``a`` fixed while the points move) confirm eq. (24) and (26) as
    printed. The ``omega_z`` entry is ``-1`` for any scene and any weights (to rounding): the
    ``omega_z`` column of ``sum_i a_i L_xn_i`` is ``(p1_y, -p1_x) = -|p1| v1_perp``. The other
    entries depend on the depths: a translation also turns ``alpha_m``.

    Parameters
    ----------
    x_n
        ``(..., N, 2)`` image points on the unit circle, ``N >= 2``.
    d
        ``(..., N)`` horizontal distances in metres, > 0.
    z_n
        ``(..., N)`` ratios ``Z / d``.
    a
        ``(..., N)`` weights from :func:`virtual_point_weights`, fixed (broadcast as in
        :func:`virtual_point`).
    sign
        Radial sign of the mirror (+1 convex, -1 concave). Reflecting every point shifts
        ``alpha_m`` by ``pi``, so the matrix is evaluated at ``u = sign * x_n``.

    Returns
    -------
    numpy.ndarray
        ``(..., 6)``: ``d alpha_m / dt = L_alpha_m tau`` (rad/m, then dimensionless).

    Raises
    ------
    ValueError
        For NaN/inf, ``d <= 0``, points off the unit circle, fewer than 2 points, mismatched
        shapes, a sign other than +-1, or ``|p1| < 1e-9``.
    """
    s = check_sign(sign)
    x, dd, zz = check_scene(x_n, d, z_n, min_points=2)
    w = check_weights(a, x)
    u = s * x
    p = _p1(u, w)
    norm = check_p1(p)
    v = p / norm[..., None]
    summed = np.sum(w[..., None, None] * _lxn(u, dd, zz), axis=-3)  # (..., 2, 6)
    projector = np.eye(2) - v[..., :, None] * v[..., None, :]  # I - v1 v1^T
    l_v1 = projector @ summed / norm[..., None, None]  # eq. (24), (..., 2, 6)
    out: NDArray[np.float64] = v[..., 0, None] * l_v1[..., 1, :] - v[..., 1, None] * l_v1[..., 0, :]
    return out  # eq. (26)
