"""Finite differences of the features, for the teaching notebook ``notebooks/02_*``.

The notebook checks the analytic interaction matrices of :mod:`radial_ibvs_gym.features`
(eq. 14-26) against these: :func:`finite_difference_interaction` moves the points along the 6
unit camera twists and differentiates a feature numerically, :func:`interaction_error` is the
tests' error measure, :func:`column_table` prints an analytic and a numeric row side by side.
It holds no library logic of its own.

Frames and units as everywhere in the package (``docs/conventions.md``): camera frame, metres,
radians; a camera twist is ``(v_x, v_y, v_z, omega_x, omega_y, omega_z)``, m/s and rad/s.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from radial_ibvs_gym._validation import as_float_array, check_last_dim
from radial_ibvs_gym.camera import RadialPoints, radial_points
from radial_ibvs_gym.geometry import apply_twist_to_points, wrap_angle

__all__ = ["TWIST_COLUMNS", "column_table", "finite_difference_interaction", "interaction_error"]

#: Names of the 6 columns of an interaction matrix: camera twist ``(v, omega)``, camera frame.
TWIST_COLUMNS: tuple[str, ...] = ("v_x", "v_y", "v_z", "w_x", "w_y", "w_z")


def finite_difference_interaction(
    feature: Callable[[RadialPoints], NDArray[np.float64]],
    points_cam: ArrayLike,
    *,
    sign: int = 1,
    step: float = 1e-5,
    angle: bool = False,
    stencil: Literal[3, 5] = 5,
) -> NDArray[np.float64]:
    """Numerical interaction matrix of a feature: central differences along the 6 unit twists.

    For each unit camera twist ``tau_k`` (``v_x, v_y, v_z`` in m/s, then ``omega_x, omega_y,
    omega_z`` in rad/s) the static points are moved exactly along ``exp(t tau_k)``
    (:func:`~radial_ibvs_gym.geometry.apply_twist_to_points`), the feature is evaluated on
    their radial points (eq. 9) and differentiated in ``t``. Column ``k`` of the result is
    then comparable with column ``k`` of the analytic ``L`` (``ds/dt = L tau``).

    Parameters
    ----------
    feature
        Maps :class:`~radial_ibvs_gym.camera.RadialPoints` of ``(..., N, 3)`` points to a
        feature array ``(..., F)`` or ``(...)``, e.g. ``lambda r: c_ij(r.x_n)``.
    points_cam
        ``(..., N, 3)`` points in the camera frame, metres (batches allowed).
    sign
        Radial sign passed to :func:`~radial_ibvs_gym.camera.radial_points`.
    step
        ``h``: time step of the differences, seconds (a displacement of ``h`` metres or
        radians), > 0.
    angle
        Wrap the differences to ``(-pi, pi]`` (for angle features such as ``alpha``).
    stencil
        ``3``: ``(f(h) - f(-h)) / 2h`` (error O(h^2)); ``5``:
        ``(8 (f(h) - f(-h)) - (f(2h) - f(-2h))) / 12h`` (error O(h^4), the tests' choice).

    Returns
    -------
    numpy.ndarray
        ``(..., F, 6)`` (or ``(..., 6)`` for a scalar feature): one column per twist.

    Raises
    ------
    ValueError
        For a non-positive step or a stencil other than 3 or 5.
    """
    if not (np.isfinite(step) and step > 0.0):
        raise ValueError(f"step must be positive, got {step!r}")
    if stencil not in (3, 5):
        raise ValueError(f"stencil must be 3 or 5, got {stencil!r}")
    p = as_float_array(points_cam, "points_cam")
    check_last_dim(p, 3, "points_cam")
    stacked = np.broadcast_to(p, (6, *p.shape))
    twists = np.eye(6).reshape(6, *([1] * (p.ndim - 2)), 6)

    def diff(h: float) -> NDArray[np.float64]:
        plus = feature(radial_points(apply_twist_to_points(stacked, twists, h), sign))
        minus = feature(radial_points(apply_twist_to_points(stacked, twists, -h), sign))
        delta = np.asarray(plus - minus, dtype=np.float64)
        return np.asarray(wrap_angle(delta), dtype=np.float64) if angle else delta

    if stencil == 3:
        derivative = diff(step) / (2.0 * step)
    else:
        derivative = (8.0 * diff(step) - diff(2.0 * step)) / (12.0 * step)
    return np.moveaxis(derivative, 0, -1)


def interaction_error(analytic: ArrayLike, numeric: ArrayLike, floor: float = 1e-3) -> float:
    """Largest entrywise ``|L - L_fd| / max(|L_fd|, floor)`` (the tests' error measure).

    Parameters
    ----------
    analytic, numeric
        Arrays of the same shape: analytic and finite-difference interaction matrices.
    floor
        Absolute floor of the denominator, for entries that are (nearly) zero.

    Returns
    -------
    float
        The largest relative error (dimensionless).

    Raises
    ------
    ValueError
        If the shapes differ.
    """
    a = as_float_array(analytic, "analytic")
    b = as_float_array(numeric, "numeric")
    if a.shape != b.shape:
        raise ValueError(f"shapes differ: analytic {a.shape}, numeric {b.shape}")
    return float(np.max(np.abs(a - b) / np.maximum(np.abs(b), floor)))


def column_table(
    rows: Mapping[str, ArrayLike],
    columns: Sequence[str] = TWIST_COLUMNS,
    fmt: str = "{:+.6f}",
) -> str:
    """Format named rows of numbers as a plain-text table with one header line.

    Parameters
    ----------
    rows
        Row label -> ``(C,)`` numbers (e.g. an analytic and a finite-difference row of an
        interaction matrix).
    columns
        The ``C`` column headers (default: the twist components of :data:`TWIST_COLUMNS`).
    fmt
        Format of one number.

    Returns
    -------
    str
        The table, lines separated by newlines, columns right-aligned.

    Raises
    ------
    ValueError
        If a row does not have one number per column.
    """
    cells = {
        label: [fmt.format(float(v)) for v in np.ravel(as_float_array(row, label))]
        for label, row in rows.items()
    }
    for label, values in cells.items():
        if len(values) != len(columns):
            raise ValueError(f"row {label!r} has {len(values)} numbers for {len(columns)} columns")
    width = max([len(c) for c in columns] + [len(v) for vs in cells.values() for v in vs])
    first = max([len(label) for label in cells] + [0])
    lines = [" " * first + "".join(f"  {c:>{width}}" for c in columns)]
    lines += [
        f"{label:<{first}}" + "".join(f"  {v:>{width}}" for v in values)
        for label, values in cells.items()
    ]
    return "\n".join(lines)
