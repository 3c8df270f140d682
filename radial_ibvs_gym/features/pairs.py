"""Pairwise features ``c_ij = x_ni^T x_nj`` for the camera translation (eq. 12, 13, 17, 18).

``c_ij`` is the cosine of the angle between two image points on the unit circle. It is
invariant to a rotation about the mirror axis (its ``omega_z`` column is zero, eq. 17-18), and
to a translation along it (``v_z`` column zero), so on a plane it only sees ``(v_x, v_y)``.

Pair order: for ``N`` points the ``M = N (N - 1) / 2`` pairs ``(i, j)``, ``i < j``, are listed
row by row, ``(0, 1), (0, 2), ..., (0, N-1), (1, 2), ..., (N-2, N-1)``, exactly as
``numpy.triu_indices(N, 1)``; every ``(..., M)`` array of this module uses that order.
"""

from __future__ import annotations

import functools
import operator

import numpy as np
from numpy.typing import ArrayLike, NDArray

from radial_ibvs_gym.features._checks import check_points, check_scene, check_sign

__all__ = ["L_cij", "c_ij", "pair_indices"]


def pair_indices(n: int) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """Return the indices ``(i, j)`` of the point pairs of the ``c_ij`` features, ``i < j``.

    Parameters
    ----------
    n
        Number of points ``N`` (>= 2).

    Returns
    -------
    tuple of numpy.ndarray
        Two ``(M,)`` integer arrays, ``M = N (N - 1) / 2``, in row-major order
        ``(0, 1), (0, 2), ..., (0, N-1), (1, 2), ..., (N-2, N-1)``
        (identical to ``numpy.triu_indices(n, 1)``).

    Raises
    ------
    ValueError
        If ``n`` is not an integer >= 2.
    """
    try:
        count = operator.index(n)
    except TypeError as exc:
        raise ValueError(f"n must be an integer number of points, got {n!r}") from exc
    if count < 2:
        raise ValueError(f"n = {count}: at least 2 points are needed to form a pair")
    i, j = _pairs(count)
    return i.copy(), j.copy()


@functools.lru_cache(maxsize=64)
def _pairs(n: int) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """:func:`pair_indices` for ``n >= 2`` points, computed once per ``n`` (read-only)."""
    i, j = np.triu_indices(n, 1)
    i.flags.writeable = j.flags.writeable = False
    return i, j


def _cij(x: NDArray[np.float64]) -> NDArray[np.float64]:
    i, j = _pairs(x.shape[-2])
    xs, ys = x[..., 0], x[..., 1]  # two products and a sum: as np.sum over the last axis
    out: NDArray[np.float64] = xs[..., i] * xs[..., j] + ys[..., i] * ys[..., j]
    return out


def c_ij(x_n: ArrayLike) -> NDArray[np.float64]:
    """Inner products of all pairs of normalised image points, eq. (12).

    Parameters
    ----------
    x_n
        ``(..., N, 2)`` normalised image points on the unit circle, ``N >= 2``.

    Returns
    -------
    numpy.ndarray
        ``(..., M)`` values ``c_ij = x_ni^T x_nj`` in ``[-1, 1]`` (dimensionless), in the order
        of :func:`pair_indices`.

    Raises
    ------
    ValueError
        For NaN/inf, points off the unit circle, or fewer than 2 points.
    """
    return _cij(check_points(x_n, min_points=2))


def L_cij(x_n: ArrayLike, d: ArrayLike, z_n: ArrayLike, *, sign: int = 1) -> NDArray[np.float64]:
    """Interaction matrices of the pairwise features ``c_ij``, eq. (13), (17), (18).

    With ``c = c_ij``, ``z_ij = z_ni - c z_nj`` and ``z_ji = z_nj - c z_ni``::

        L_cij_v     = [(-1/d_j + c/d_i) x_ni^T + (-1/d_i + c/d_j) x_nj^T,  0]     (eq. 17)
        L_cij_omega = [y_nj z_ij + y_ni z_ji,  -x_nj z_ij - x_ni z_ji,  0]          (eq. 18)

    obtained from ``dc_ij/dt = x_nj^T dx_ni/dt + x_ni^T dx_nj/dt`` (eq. 13) and eq. (14)-(16).
    Finite differences confirm eq. (17)-(18) as printed (signs, the pairing of ``d_i``/``d_j``
    with ``x_ni``/``x_nj``, and the definitions of ``z_ij``, ``z_ji``). The ``v_z`` and
    ``omega_z`` columns are exactly zero.

    Parameters
    ----------
    x_n
        ``(..., N, 2)`` normalised image points on the unit circle, ``N >= 2``.
    d
        ``(..., N)`` horizontal distances in metres, > 0.
    z_n
        ``(..., N)`` ratios ``Z / d``.
    sign
        Radial sign of the mirror (+1 convex, -1 concave). ``c_ij`` does not change when every
        point is reflected, so the matrix is evaluated at ``u = sign * x_n``.

    Returns
    -------
    numpy.ndarray
        ``(..., M, 6)`` with ``M = N (N - 1) / 2`` in the order of :func:`pair_indices`;
        ``dc_ij/dt = L_cij tau`` (1/m for the translational columns, dimensionless for the
        rotational ones).

    Raises
    ------
    ValueError
        For NaN/inf, ``d <= 0``, points off the unit circle, fewer than 2 points, mismatched
        shapes or a sign other than +-1.
    """
    s = check_sign(sign)
    x, dd, zz = check_scene(x_n, d, z_n, min_points=2)
    u = s * x
    i, j = _pairs(u.shape[-2])
    ui, uj = u[..., i, :], u[..., j, :]
    di, dj = dd[..., i], dd[..., j]
    zi, zj = zz[..., i], zz[..., j]
    c = np.sum(ui * uj, axis=-1)
    k_i = -1.0 / dj + c / di
    k_j = -1.0 / di + c / dj
    lv = k_i[..., None] * ui + k_j[..., None] * uj
    z_ij = zi - c * zj
    z_ji = zj - c * zi
    w_x = uj[..., 1] * z_ij + ui[..., 1] * z_ji
    w_y = -uj[..., 0] * z_ij - ui[..., 0] * z_ji
    zero = np.zeros_like(c)
    return np.stack([lv[..., 0], lv[..., 1], zero, w_x, w_y, zero], axis=-1)
