"""The paper's IBVS (eq. 27-38) for a batch of robots at once, as pure numpy.

:class:`~agents.analytic.ibvs_policy.IBVSPolicy` computes one robot at a time (a goal model per
goal image, cached). Stepping thousands of robots, as a residual policy trained on the native
vector env does, needs the same maths over a leading batch axis. Here each row keeps its own
landmark mask (the landmarks visible now and in the goal image): hidden landmarks get zero weight,
so the masked least-squares problems of one row do not see them. Closed-form ``2 x 2`` solves
replace the pseudo-inverses (``L*_c`` has two columns on a plane), which is the same solution
whenever the matrix has rank 2; rows where it does not (or with fewer than 3 landmarks, or a
degenerate goal image) get a zero command, as the scalar policy gives them.

The tests check every row against :class:`~agents.analytic.ibvs_policy.IBVSPolicy` on random rooms.
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from numpy.typing import NDArray

from agents.analytic.smooth_control import curvature, ego_polar
from radial_ibvs_gym.features import L_alpha_m, L_cij, c_ij, pair_indices
from radial_ibvs_gym.geometry import wrap_angle

__all__ = ["ibvs_twist_batch", "park_command_batch"]

F64 = NDArray[np.float64]
ArrayLike2 = NDArray[np.floating] | NDArray[np.bool_]
#: smallest ``sigma_min / sigma_max`` of a 2-column matrix treated as rank 2 (as the features do)
_RANK_TOL = 1e-9


def _solve_2x2(
    g00: F64, g01: F64, g11: F64, r0: F64, r1: F64
) -> tuple[F64, F64, NDArray[np.bool_]]:
    """Solve ``[[g00, g01], [g01, g11]] x = r`` row-wise; ``ok`` where the matrix has rank 2."""
    det = g00 * g11 - g01 * g01
    half = 0.5 * (g00 + g11)
    lam_max = half + np.sqrt(np.maximum(half * half - det, 0.0))
    ok = det > (_RANK_TOL**2) * lam_max * lam_max  # sigma_min / sigma_max > _RANK_TOL
    safe = np.where(ok, det, 1.0)
    return (g11 * r0 - g01 * r1) / safe, (g00 * r1 - g01 * r0) / safe, ok


def ibvs_twist_batch(
    points: ArrayLike2,
    goal_points: ArrayLike2,
    goal_depths: ArrayLike2,
    visible: ArrayLike2,
    lam: float = 0.5,
    compensation: Literal["derived", "printed"] = "derived",
    frame_change: bool = True,
) -> tuple[F64, F64, NDArray[np.bool_]]:
    """Camera velocity and rotation to the goal of the paper's IBVS, for a batch (eq. 27-37).

    Parameters
    ----------
    points, goal_points
        ``(B, 2N)`` current and goal image points as the env observes them (zeros where
        hidden, ``N`` landmarks or slots).
    goal_depths
        ``(B, N)`` goal depths ``d*``, metres.
    visible
        ``(B, N)`` visibility now (1 or 0).
    lam
        The gain ``lambda``, 1/s.
    compensation
        Sign of eq. (30)'s compensation terms (:func:`agents.analytic.ibvs_maths.ibvs_twist`).
    frame_change
        Rotate ``v*`` into the current frame by ``gamma`` (eq. 36-37); ``False`` is the
        ``no-frame-change`` variant, ``v = -v*``.

    Returns
    -------
    v
        ``(B, 2)`` camera velocity ``(v_x, v_y)`` in the current frame, m/s.
    gamma
        ``(B,)`` estimated rotation to the goal orientation, radians.
    ok
        ``(B,)`` whether the row has an estimate (at least 3 landmarks seen now and in the
        goal image, a non-degenerate goal image); ``v`` and ``gamma`` are 0 elsewhere.
    """
    x_now = np.asarray(points, dtype=np.float64)
    b = x_now.shape[0]
    x_now = x_now.reshape(b, -1, 2)
    x_goal = np.asarray(goal_points, dtype=np.float64).reshape(b, -1, 2)
    d_goal = np.asarray(goal_depths, dtype=np.float64).reshape(b, -1)
    norm_now = np.hypot(x_now[..., 0], x_now[..., 1])
    norm_goal = np.hypot(x_goal[..., 0], x_goal[..., 1])
    mask = (
        (np.asarray(visible, dtype=np.float64).reshape(b, -1) > 0.5)
        & (norm_now > 0.5)
        & (norm_goal > 0.5)
    )
    ok = mask.sum(axis=-1) >= 3
    dummy = np.array([1.0, 0.0])
    m3 = mask[..., None]
    x_now = np.where(m3, x_now / np.where(m3, norm_now[..., None], 1.0), dummy)
    x_goal = np.where(m3, x_goal / np.where(m3, norm_goal[..., None], 1.0), dummy)
    d_goal = np.where(mask & (d_goal > 0), d_goal, 1.0)
    # eq. (27-29): a = B^T (B B^T)^-1 e1 with B = X*^T over the masked points (p1* = (1, 0))
    xm = np.where(m3, x_goal, 0.0)
    g00 = np.sum(xm[..., 0] ** 2, axis=-1)
    g01 = np.sum(xm[..., 0] * xm[..., 1], axis=-1)
    g11 = np.sum(xm[..., 1] ** 2, axis=-1)
    one, zero = np.ones(b), np.zeros(b)
    s0, s1, rank2 = _solve_2x2(g00, g01, g11, one, zero)
    ok &= rank2
    weights = xm[..., 0] * s0[:, None] + xm[..., 1] * s1[:, None]
    first = np.zeros_like(weights)
    first[:, 0] = 1.0  # a harmless stand-in for rows without an estimate (masked out below)
    weights = np.where(ok[:, None], weights, first)
    # eq. (12), (17): the goal's c*_ij and L*_c (v_x, v_y columns) over the masked pairs
    i, j = pair_indices(x_goal.shape[-2])
    pair_ok = mask[:, i] & mask[:, j]
    zeros = np.zeros_like(d_goal)
    L_c = np.where(pair_ok[..., None], L_cij(x_goal, d_goal, zeros)[..., :2], 0.0)
    error = np.where(pair_ok, c_ij(x_goal) - c_ij(x_now), 0.0)  # c* - c
    a00 = np.sum(L_c[..., 0] ** 2, axis=-1)
    a01 = np.sum(L_c[..., 0] * L_c[..., 1], axis=-1)
    a11 = np.sum(L_c[..., 1] ** 2, axis=-1)
    r0 = np.sum(L_c[..., 0] * error, axis=-1)
    r1 = np.sum(L_c[..., 1] * error, axis=-1)
    p0, p1, rank2 = _solve_2x2(a00, a01, a11, r0, r1)  # pinv(L*_c) (c* - c)
    ok &= rank2
    v_star = -lam * np.stack([p0, p1], axis=-1)  # eq. (30)
    # eq. (24)-(26), (30), (37): alpha_m and gamma
    p_now = np.sum(weights[..., None] * x_now, axis=-2)
    error_alpha = wrap_angle(-np.arctan2(p_now[:, 1], p_now[:, 0]))  # alpha*_m = 0
    L_alpha = L_alpha_m(x_goal, d_goal, zeros, weights)[:, :2]
    sign = 1.0 if compensation == "derived" else -1.0
    omega_star = lam * error_alpha + sign * np.sum(L_alpha * v_star, axis=-1)
    gamma = -omega_star / lam
    if frame_change:  # eq. (36): v = -R(gamma) v*
        c, s = np.cos(gamma), np.sin(gamma)
        vx, vy = v_star[:, 0], v_star[:, 1]
        v = -np.stack([c * vx - s * vy, s * vx + c * vy], axis=-1)
    else:
        v = -v_star
    v = np.where(ok[:, None], v, 0.0)
    return v, np.where(ok, gamma, 0.0), ok


def park_command_batch(
    v: F64,
    gamma: F64,
    lam: float,
    k1: float,
    k2: float,
    v_max: float,
    omega_max: float,
    stop_radius: float,
    stop_heading: float,
    rotate_radius: float,
    allow_backward: bool = False,
) -> tuple[F64, F64]:
    """:func:`agents.analytic.ibvs_maths.park_command` for a batch: robot speeds from eq. (38).

    Parameters
    ----------
    v
        ``(B, 2)`` camera velocities in the current frame, m/s.
    gamma
        ``(B,)`` estimated rotations to the goal orientation, radians.
    lam, k1, k2, v_max, omega_max, stop_radius, stop_heading, rotate_radius, allow_backward
        As in :func:`~agents.analytic.ibvs_maths.park_command` (1/s, m/s, rad/s, metres, radians).

    Returns
    -------
    v_l, omega
        ``(B,)`` linear (m/s) and angular (rad/s) speeds.
    """
    v = np.asarray(v, dtype=np.float64)
    gamma = np.asarray(gamma, dtype=np.float64)
    speed = np.hypot(v[:, 0], v[:, 1])
    r = speed / lam
    delta = np.arctan2(v[:, 1], v[:, 0])
    target = np.stack([r * np.cos(delta), r * np.sin(delta), gamma], axis=-1)
    reverse = allow_backward & (target[:, 0] < 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        kappa = np.where(
            reverse,
            -curvature(*ego_polar(target, backward=True), k1, k2),
            curvature(*ego_polar(target), k1, k2),
        )
    v_l = np.where(reverse, -speed, speed)
    omega = kappa * v_l
    moving = speed > 1e-12
    factor = np.maximum.reduce(
        [np.ones_like(speed), np.abs(v_l) / v_max, np.abs(np.where(moving, omega, 0.0)) / omega_max]
    )
    v_l = np.where(moving, v_l / factor, 0.0)
    omega = np.where(moving, omega / factor, 0.0)
    rotate = r < rotate_radius  # final approach
    v_l = np.where(rotate, v[:, 0], v_l)
    omega = np.where(rotate, np.clip(lam * gamma, -omega_max, omega_max), omega)
    stop = (r < stop_radius) & (np.abs(gamma) < stop_heading)
    return np.where(stop, 0.0, v_l), np.where(stop, 0.0, omega)
