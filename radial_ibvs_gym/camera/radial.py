"""The radial camera model (paper Section 2.1, eq. 4-9).

For a camera whose optical axis is the symmetry axis of the mirror, the image point, the
principal point (centre of distortion) and the projection of the 3D point along the axis all lie
on one radial line. Normalising the image point onto the unit circle therefore removes
everything the mirror and the lens do along that line: the normalised point ``x_n`` depends only
on the 3D point's horizontal direction (eq. 9), for central *and* non-central configurations,
and computing it from pixels needs only the principal point and ``rho_f = fx / fy`` (eq. 7).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from radial_ibvs_gym._validation import as_float_array, check_finite, check_last_dim

__all__ = ["RadialPoints", "normalise_pixels", "radial_points"]

#: Horizontal distances below this (metres) count as "on the optical axis" (x_n undefined).
AXIS_EPS = 1e-12


class RadialPoints(NamedTuple):
    """Normalised radial image points with the depths the interaction matrices need.

    Attributes
    ----------
    x_n
        ``(..., N, 2)`` normalised points on the unit circle, eq. (9).
    d
        ``(..., N)`` horizontal distances ``sqrt(X^2 + Y^2)`` in metres (the paper's ``d``,
        also its "depth r*").
    z_n
        ``(..., N)`` ratios ``Z / d`` (dimensionless); they only enter the ``omega_x``,
        ``omega_y`` columns of the interaction matrices.
    """

    x_n: NDArray[np.float64]
    d: NDArray[np.float64]
    z_n: NDArray[np.float64]


def radial_points(points: ArrayLike, sign: int = 1) -> RadialPoints:
    """Normalised image points from 3D points in the camera frame, eq. (9).

    Parameters
    ----------
    points
        ``(..., N, 3)`` points ``(X, Y, Z)`` in the camera frame, metres (z along the mirror
        axis).
    sign
        ``+1`` for convex mirrors (the image point lies on the same side of the axis as the
        scene point), ``-1`` for concave ones such as the central ellipsoidal mirror, whose image
        is point-reflected through the principal point. See
        :attr:`~radial_ibvs_gym.camera.mirrors.QuadricMirror.radial_sign`.

    Returns
    -------
    RadialPoints
        ``x_n = sign * (X, Y) / d`` with ``d = sqrt(X^2 + Y^2)``, and ``d``, ``z_n = Z / d``.

    Raises
    ------
    ValueError
        If a point is NaN/inf, or lies on the optical axis (``d = 0``), where ``x_n`` is
        undefined.
    """
    p = as_float_array(points, "points")
    check_last_dim(p, 3, "points")
    check_finite(p, "points")
    if sign not in (1, -1):
        raise ValueError(f"sign must be +1 or -1, got {sign!r}")
    d = np.hypot(p[..., 0], p[..., 1])
    if np.any(d <= AXIS_EPS):
        index = tuple(int(i) for i in np.argwhere(d <= AXIS_EPS)[0])
        raise ValueError(
            f"point {p[index].tolist()} at index {index} lies on the optical axis (d = 0): "
            "its radial image point x_n is undefined"
        )
    x_n = sign * p[..., :2] / d[..., None]
    return RadialPoints(x_n=x_n, d=d, z_n=p[..., 2] / d)


def normalise_pixels(
    pixels: ArrayLike, principal_point: ArrayLike, rho_f: float = 1.0
) -> NDArray[np.float64]:
    """Normalised points on the unit circle from pixel coordinates, eq. (7).

    Only the principal point ``(mu_x, mu_y)`` (the centre of distortion) and the focal ratio
    ``rho_f = fx / fy`` (eq. 8) are needed: the focal length itself and the mirror shape cancel.

    Parameters
    ----------
    pixels
        ``(..., 2)`` image points ``(x_d, y_d)`` in pixels.
    principal_point
        ``(2,)`` or broadcastable ``(..., 2)``: ``(mu_x, mu_y)`` in pixels.
    rho_f
        Focal ratio ``fx / fy`` (dimensionless, > 0).

    Returns
    -------
    numpy.ndarray
        ``(..., 2)`` points ``x_n`` with ``|x_n| = 1``.

    Raises
    ------
    ValueError
        For NaN/inf input, a non-positive ``rho_f``, or a pixel at the principal point.
    """
    px = as_float_array(pixels, "pixels")
    mu = as_float_array(principal_point, "principal_point")
    check_last_dim(px, 2, "pixels")
    check_last_dim(mu, 2, "principal_point")
    check_finite(px, "pixels")
    check_finite(mu, "principal_point")
    if not (np.isfinite(rho_f) and rho_f > 0):
        raise ValueError(f"rho_f must be finite and positive, got {rho_f!r}")
    return normalise_unchecked(px, mu, rho_f)


def normalise_unchecked(
    px: NDArray[np.float64], mu: NDArray[np.float64], rho_f: float
) -> NDArray[np.float64]:
    """:func:`normalise_pixels` without the input checks (a hot path whose input is valid).

    Parameters
    ----------
    px
        ``(..., 2)`` finite pixels.
    mu
        ``(2,)`` or broadcastable ``(..., 2)`` finite principal point, pixels.
    rho_f
        Finite, positive focal ratio.

    Returns
    -------
    numpy.ndarray
        ``(..., 2)`` points on the unit circle, the same bits as :func:`normalise_pixels`.

    Raises
    ------
    ValueError
        For a pixel at the principal point.
    """
    du = px[..., 0] - mu[..., 0]
    dv = px[..., 1] - mu[..., 1]
    # eq. (7) multiplies through by fx: x_n = (du, rho_f dv) / sqrt(du^2 + rho_f^2 dv^2),
    # which is eq. (5) with x_m = du / fx and y_m = dv / fy.
    dv = rho_f * dv
    norm = np.hypot(du, dv)
    if np.any(norm == 0.0):
        index = tuple(int(i) for i in np.argwhere(norm == 0.0)[0])
        raise ValueError(
            f"pixel {px[index].tolist()} at index {index} is the principal point: "
            "its direction on the unit circle is undefined"
        )
    return np.stack([du / norm, dv / norm], axis=-1)
