"""Input checks of the features layer: every degenerate input gives a ``ValueError`` naming it.

Private helpers; the public functions call them once and then work on validated float arrays.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from radial_ibvs_gym._validation import as_float_array, check_finite, check_last_dim

__all__ = [
    "MIN_P1_NORM",
    "UNIT_TOL",
    "check_p1",
    "check_points",
    "check_scene",
    "check_sign",
    "check_weights",
]

#: Largest accepted deviation of ``|x_n|`` from 1 (eq. 9 puts every point on the unit circle).
UNIT_TOL = 1e-6
#: Virtual points shorter than this have no defined direction (eq. 23).
MIN_P1_NORM = 1e-9


def _first(mask: NDArray[np.bool_]) -> tuple[int, ...]:
    return tuple(int(i) for i in np.argwhere(mask)[0])


def check_points(x_n: ArrayLike, min_points: int, name: str = "x_n") -> NDArray[np.float64]:
    """Return ``x_n`` as a float array of shape ``(..., N, 2)`` after checking it.

    Raises ``ValueError`` for a wrong shape, fewer than ``min_points`` points, NaN/inf, or a
    point off the unit circle by more than :data:`UNIT_TOL`.
    """
    x = as_float_array(x_n, name)
    check_last_dim(x, 2, name)
    if x.ndim < 2:
        raise ValueError(f"{name} must have shape (..., N, 2), got shape {x.shape}")
    if x.shape[-2] < min_points:
        raise ValueError(
            f"{name} has {x.shape[-2]} point(s) (shape {x.shape}): "
            f"at least {min_points} points are needed"
        )
    check_finite(x, name)
    deviation = np.abs(np.hypot(x[..., 0], x[..., 1]) - 1.0)
    bad = deviation > UNIT_TOL
    if np.any(bad):
        index = _first(bad)
        raise ValueError(
            f"{name}{list(index)} = {x[index].tolist()} is not of unit norm "
            f"(|x_n| = {np.hypot(*x[index]):.9g}, tolerance {UNIT_TOL}): "
            "normalise the points onto the unit circle (eq. 9)"
        )
    return x


def check_scene(
    x_n: ArrayLike, d: ArrayLike, z_n: ArrayLike, min_points: int
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Check ``x_n (..., N, 2)``, ``d (..., N)``, ``z_n (..., N)`` together and return them.

    ``d`` and ``z_n`` must have exactly the shape ``x_n.shape[:-1]``; ``d`` must be positive.
    """
    x = check_points(x_n, min_points)
    dd = as_float_array(d, "d")
    zz = as_float_array(z_n, "z_n")
    for arr, name in ((dd, "d"), (zz, "z_n")):
        if arr.shape != x.shape[:-1]:
            raise ValueError(
                f"{name} must have shape x_n.shape[:-1] = {x.shape[:-1]}, got shape {arr.shape}"
            )
        check_finite(arr, name)
    bad = dd <= 0.0
    if np.any(bad):
        index = _first(bad)
        raise ValueError(
            f"d{list(index)} = {float(dd[index])!r} is not positive: a point on the optical axis "
            "(d = 0) has no radial image point and the interaction matrices divide by d"
        )
    return x, dd, zz


def check_weights(a: ArrayLike, x: NDArray[np.float64]) -> NDArray[np.float64]:
    """Check virtual-point weights ``a (..., N)`` against validated points ``x (..., N, 2)``.

    The leading dimensions of ``a`` only need to broadcast with those of ``x`` (one goal's
    weights serve a whole batch of scenes).
    """
    w = as_float_array(a, "a")
    n = x.shape[-2]
    if w.ndim == 0 or w.shape[-1] != n:
        raise ValueError(
            f"a must have shape (..., N) with N = {n} (the number of points in x_n), "
            f"got shape {w.shape}"
        )
    try:
        np.broadcast_shapes(w.shape[:-1], x.shape[:-2])
    except ValueError as exc:
        raise ValueError(
            f"the batch shape of a {w.shape[:-1]} does not broadcast with that of x_n "
            f"{x.shape[:-2]}"
        ) from exc
    check_finite(w, "a")
    return w


def check_p1(p1: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return ``|p1|`` (shape ``(...)``), raising if the virtual point is (nearly) zero."""
    norm = np.hypot(p1[..., 0], p1[..., 1])
    bad = norm < MIN_P1_NORM
    if np.any(bad):
        index = _first(bad) if norm.ndim else ()
        raise ValueError(
            f"virtual point p1{list(index)} = {p1[index].tolist()} has norm "
            f"{float(norm[index]):.3g} < {MIN_P1_NORM}: its direction v1 (eq. 23) and "
            "alpha_m are undefined; the image is too far from the goal the weights were "
            "computed for"
        )
    return norm


def check_sign(sign: Any) -> int:
    """Return ``sign`` if it is +1 or -1 (the radial sign of the mirror)."""
    if isinstance(sign, bool) or sign not in (1, -1):
        raise ValueError(f"sign must be +1 or -1, got {sign!r}")
    return int(sign)
