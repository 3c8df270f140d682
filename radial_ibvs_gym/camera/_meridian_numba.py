"""The hyperboloid meridian root-find as one numba loop (see :mod:`.meridian_jit`).

Each function repeats, for one point, the numpy expressions of
:class:`~radial_ibvs_gym.camera.meridian.MeridianSolver` and its table (the same operations in
the same order; Python's left-to-right evaluation is numpy's). ``error_model="numpy"``: a
division by zero gives inf or NaN as in numpy; no ``fastmath``: no fused multiply-adds.
"""

from __future__ import annotations

import math
from typing import Any

import numba

__all__ = ["solve_hyperboloid"]

_jit = numba.njit(cache=True, nogil=True, error_model="numpy")


@_jit
def _terms(
    s: float, a: float, b: float, k: float, camera_z: float
) -> tuple[float, float, float, float, float]:
    """``MeridianSolver._terms`` of a hyperboloid (``Hyperboloid.profile``) at radius ``s``."""
    r = abs(s)
    q = r / a
    root = math.sqrt(1.0 + q * q)
    mz = b * root
    slope = k * r / root
    if s < 0.0:
        slope = -slope
    ux = -s
    uz = camera_z - mz
    dot = ux * slope - uz
    nn = 1.0 + slope * slope
    wx = 2.0 * dot * slope - nn * ux
    wz = -2.0 * dot - nn * uz
    return mz, slope, dot, wx, wz


@_jit
def _residual(
    s: float, rho_p: float, z_p: float, a: float, b: float, k: float, camera_z: float
) -> tuple[float, bool]:
    """``MeridianSolver.residual`` at one point: ``G(s)`` and whether ``s`` is valid."""
    mz, slope, dot, wx, wz = _terms(s, a, b, k, camera_z)
    dx = rho_p - s
    dz = z_p - mz
    g = wx * dz - wz * dx
    valid = (wx * dx + wz * dz > 0.0) and (dot > 0.0) and (dx * slope - dz > 0.0)
    return g, valid


@_jit
def solve_hyperboloid(
    rho: Any,
    z: Any,
    a: float,
    b: float,
    k: float,
    camera_z: float,
    cells: Any,
    n_directions: int,
    n_inverse: int,
    d_direction: float,
    d_inverse: float,
    iterations: int,
    out: Any,
    to_grid: Any,
) -> None:
    """Write each point's root into ``out`` (NaN: none), or mark it ``to_grid``.

    ``rho``, ``z``: ``(K,)`` the points (mirror frame, metres); ``a``, ``b``: the semi-axes,
    ``k = b / a**2``; ``cells`` ``(C, 5)`` and the other scalars: the table's
    (``_Table``); ``out`` ``(K,)`` float64 and ``to_grid`` ``(K,)`` bool are written.
    """
    nan = math.nan
    for i in range(rho.shape[0]):
        rho_p, z_p = rho[i], z[i]
        out[i] = nan
        to_grid[i] = False
        # _Table.lookup
        d = math.sqrt(rho_p * rho_p + z_p * z_p)
        u = (z_p / (rho_p + d) + 1.0) / d_direction
        v = 1.0 / (d * d_inverse)
        if not ((u >= 0.0) and (u < n_directions) and (v < n_inverse)):
            to_grid[i] = True  # off the table
            continue
        iu, iv = int(u), int(v)
        fu, fv = u - iu, v - iv
        row = iu * n_inverse + iv
        guess = cells[row, 0] + fu * (cells[row, 1] + fv * cells[row, 3]) + fv * cells[row, 2]
        half = cells[row, 4]
        if half == math.inf:  # no root in or near the cell: none
            continue
        if half != half:  # NaN: the grid searches the cell
            to_grid[i] = True
            continue
        # MeridianSolver.solve: both ends of the bracket
        end_a, end_b = guess - half, guess + half
        g_a, valid_a = _residual(end_a, rho_p, z_p, a, b, k, camera_z)
        g_b, valid_b = _residual(end_b, rho_p, z_p, a, b, k, camera_z)
        if not (valid_a and valid_b and g_a * g_b <= 0.0):
            to_grid[i] = True
            continue
        # MeridianSolver._illinois
        for _ in range(iterations):
            step = g_b * (end_b - end_a) / (g_b - g_a)
            s = end_b - step if math.isfinite(step) else end_b
            low = end_a if end_a < end_b else end_b
            high = end_b if end_a < end_b else end_a
            s = s if s > low else low  # np.maximum, then np.minimum
            s = s if s < high else high
            mz, _, _, wx, wz = _terms(s, a, b, k, camera_z)
            g_s = wx * (z_p - mz) - wz * (rho_p - s)
            if g_s * g_b < 0.0:
                end_a, g_a = end_b, g_b
            else:
                g_a = 0.5 * g_a
            end_b, g_b = s, g_s
        _, ok = _residual(end_b, rho_p, z_p, a, b, k, camera_z)
        if ok:
            out[i] = end_b
