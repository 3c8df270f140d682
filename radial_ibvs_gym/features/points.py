"""Per-point features: the normalised point ``x_n`` and its angle ``alpha`` (eq. 14-16, 19-21).

Conventions (see ``docs/conventions.md``): camera twist ``tau = (v_x, v_y, v_z, omega_x,
omega_y, omega_z)`` in the camera frame, a static point moves as ``dP/dt = -v - omega x P``, and
every interaction matrix ``L`` has these 6 columns with ``ds/dt = L tau``. With this convention
eq. (15), (16) and (21) hold exactly as printed (checked against central finite differences in
``tests/features/test_features_interaction.py``).

The radial sign: the printed formulas assume ``x_n = +(X, Y) / d`` (convex mirrors). For the
concave (ellipsoidal) mirror, ``x_n = -(X, Y) / d``; pass ``sign=-1`` and the matrices are
evaluated at ``u = sign * x_n`` and mapped back (``L_xn`` changes sign, ``L_alpha`` does not).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from radial_ibvs_gym.features._checks import check_points, check_scene, check_sign

__all__ = ["L_alpha", "L_xn", "alpha"]


def _lxn(
    u: NDArray[np.float64], d: NDArray[np.float64], z: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Eq. (15)-(16) for validated ``u = (X, Y) / d``: ``(..., N, 2, 6)``."""
    ux, uy = u[..., 0], u[..., 1]
    zero = np.zeros_like(d)
    row_x = (-(1.0 - ux * ux) / d, ux * uy / d, zero, -ux * uy * z, -(1.0 - ux * ux) * z, uy)
    row_y = (ux * uy / d, -(1.0 - uy * uy) / d, zero, (1.0 - uy * uy) * z, ux * uy * z, -ux)
    return np.stack([np.stack(row_x, axis=-1), np.stack(row_y, axis=-1)], axis=-2)


def L_xn(x_n: ArrayLike, d: ArrayLike, z_n: ArrayLike, *, sign: int = 1) -> NDArray[np.float64]:
    """Interaction matrices of the normalised image points, eq. (14)-(16).

    ``L_xn = [L_xn_v, L_xn_omega]`` with (``x_n = (x, y)``)::

        L_xn_v     = [[-(1 - x^2)/d,  x y / d,       0],
                      [ x y / d,      -(1 - y^2)/d,  0]]            (eq. 15)
        L_xn_omega = [[-x y z_n,      -(1 - x^2) z_n,  y],
                      [(1 - y^2) z_n,  x y z_n,       -x]]           (eq. 16)

    Derived from ``x_n = (X, Y) / d``: ``dx_n/dt = (I - x_n x_n^T) (dX, dY) / d``. The ``v_z``
    column is zero (moving along the mirror axis leaves the radial direction unchanged).
    Finite differences confirm eq. (15)-(16) as printed, with no sign change.

    Parameters
    ----------
    x_n
        ``(..., N, 2)`` normalised image points on the unit circle (eq. 9), dimensionless.
    d
        ``(..., N)`` horizontal distances ``sqrt(X^2 + Y^2)`` in metres, > 0.
    z_n
        ``(..., N)`` ratios ``Z / d``, dimensionless.
    sign
        Radial sign of the mirror used to compute ``x_n`` (+1 convex, -1 concave); see the
        module docstring.

    Returns
    -------
    numpy.ndarray
        ``(..., N, 2, 6)``: ``d x_n / dt = L_xn tau``; the translational columns are in 1/m,
        the rotational ones dimensionless.

    Raises
    ------
    ValueError
        For NaN/inf, ``d <= 0``, points off the unit circle, no point, mismatched shapes or a
        sign other than +-1.
    """
    s = check_sign(sign)
    x, dd, zz = check_scene(x_n, d, z_n, min_points=1)
    out: NDArray[np.float64] = s * _lxn(s * x, dd, zz)
    return out


def alpha(x_n: ArrayLike) -> NDArray[np.float64]:
    """Angles of the normalised image points, eq. (19): ``alpha = atan2(y_n, x_n)``.

    Parameters
    ----------
    x_n
        ``(..., N, 2)`` normalised image points on the unit circle.

    Returns
    -------
    numpy.ndarray
        ``(..., N)`` angles in radians, in ``[-pi, pi]``.

    Raises
    ------
    ValueError
        For NaN/inf, points off the unit circle, or no point.
    """
    x = check_points(x_n, min_points=1)
    out: NDArray[np.float64] = np.arctan2(x[..., 1], x[..., 0])
    return out


def L_alpha(x_n: ArrayLike, d: ArrayLike, z_n: ArrayLike, *, sign: int = 1) -> NDArray[np.float64]:
    """Interaction matrices of the point angles ``alpha``, eq. (20)-(21).

    ``L_alpha = [y_n / d, -x_n / d, 0, x_n z_n, y_n z_n, -1]`` (eq. 21), from
    ``d alpha / dt = x_n dy_n/dt - y_n dx_n/dt`` (eq. 20, which uses ``|x_n| = 1``) and eq. (14).
    Finite differences confirm eq. (21) as printed; its ``omega_z`` entry is exactly -1: a
    camera rotation about the axis turns every image point by the opposite angle.

    Parameters
    ----------
    x_n
        ``(..., N, 2)`` normalised image points on the unit circle.
    d
        ``(..., N)`` horizontal distances in metres, > 0.
    z_n
        ``(..., N)`` ratios ``Z / d``.
    sign
        Radial sign of the mirror (+1 convex, -1 concave). ``alpha`` of a point-reflected
        image is shifted by ``pi``, so ``L_alpha`` is the same for both signs once evaluated at
        ``u = sign * x_n``.

    Returns
    -------
    numpy.ndarray
        ``(..., N, 6)``: ``d alpha / dt = L_alpha tau`` (rad/m for the translational columns,
        dimensionless for the rotational ones).

    Raises
    ------
    ValueError
        As :func:`L_xn`.
    """
    s = check_sign(sign)
    x, dd, zz = check_scene(x_n, d, z_n, min_points=1)
    ux, uy = s * x[..., 0], s * x[..., 1]
    cols = (uy / dd, -ux / dd, np.zeros_like(dd), ux * zz, uy * zz, np.full_like(dd, -1.0))
    return np.stack(cols, axis=-1)
