"""The paper's IBVS (eq. 27-38) for a batch of robots at once, as pure numpy.

:class:`~radial_ibvs_agents.analytic.ibvs_policy.IBVSPolicy` computes one robot at a time (a goal
model per goal image, cached). Stepping thousands of robots, as a residual policy trained on the
native vector env does, needs the same maths over a leading batch axis. Here each row keeps its own
landmark mask (the landmarks visible now and in the goal image): hidden landmarks get zero weight,
so the masked least-squares problems of one row do not see them. Closed-form ``2 x 2`` solves
replace the pseudo-inverses (``L*_c`` has two columns on a plane), which is the same solution
whenever the matrix has rank 2; rows where it does not (or with fewer than 3 landmarks, or a
degenerate goal image) get a zero command, as the scalar policy gives them.

The tests check every row against :class:`~radial_ibvs_agents.analytic.ibvs_policy.IBVSPolicy` on
random rooms.
"""

from __future__ import annotations

from collections import OrderedDict
from dataclasses import dataclass, fields
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from radial_ibvs_agents.analytic.smooth_control import curvature, ego_polar
from radial_ibvs_gym.features import L_alpha_m, L_cij, c_ij, pair_indices
from radial_ibvs_gym.geometry import wrap_angle

__all__ = ["GoalCache", "GoalTerms", "ibvs_twist_batch", "park_command_batch"]

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


def _masked_goal(
    x_goal: F64, d_goal: F64, L_cx_all: F64, L_cy_all: F64, mask: NDArray[np.bool_]
) -> tuple[NDArray[np.bool_], F64, F64, F64, F64, F64, NDArray[np.bool_]]:
    """Compute the goal-side terms of the IBVS over the landmarks in ``mask`` ``(B, N)``.

    Returns ``ok`` ``(B,)`` (at least 3 landmarks, rank-2 goal matrices), the virtual point's
    weights ``a`` ``(B, N)`` (eq. 27-29), ``L*_alpha`` ``(B, 2)`` (eq. 26), the ``v_x`` and
    ``v_y`` columns of the masked ``L*_c`` (eq. 17, ``(B, M)`` each), its normal matrix
    ``(B, 3)`` (``a00, a01, a11``) and ``pair_ok`` ``(B, M)``. Every sum runs over a
    contiguous last axis, so a row's bits do not depend on the batch it is computed in.
    """
    b = mask.shape[0]
    ok = mask.sum(axis=-1) >= 3
    # eq. (27-29): a = B^T (B B^T)^-1 e1 with B = X*^T over the masked points (p1* = (1, 0))
    gx = np.where(mask, x_goal[..., 0], 0.0)
    gy = np.where(mask, x_goal[..., 1], 0.0)
    g00 = np.sum(gx * gx, axis=-1)
    g01 = np.sum(gx * gy, axis=-1)
    g11 = np.sum(gy * gy, axis=-1)
    s0, s1, rank2 = _solve_2x2(g00, g01, g11, np.ones(b), np.zeros(b))
    ok &= rank2
    weights = gx * s0[:, None] + gy * s1[:, None]
    first = np.zeros_like(weights)
    first[:, 0] = 1.0  # a harmless stand-in for rows without an estimate (masked out later)
    weights = np.where(ok[:, None], weights, first)
    L_alpha = L_alpha_m(x_goal, d_goal, np.zeros_like(d_goal), weights)[:, :2]
    # eq. (17): L*_c (v_x, v_y columns) over the masked pairs, and its normal matrix
    i, j = pair_indices(x_goal.shape[-2])
    pair_ok = mask[:, i] & mask[:, j]
    L_cx, L_cy = np.where(pair_ok, L_cx_all, 0.0), np.where(pair_ok, L_cy_all, 0.0)
    normal = np.stack(
        [np.sum(L_cx * L_cx, axis=-1), np.sum(L_cx * L_cy, axis=-1), np.sum(L_cy * L_cy, axis=-1)],
        axis=-1,
    )
    return ok, weights, L_alpha, L_cx, L_cy, normal, pair_ok


@dataclass
class GoalTerms:
    """What the IBVS needs of a batch of goal images: fixed for an episode (eq. 12, 17, 26-29).

    The ``seen`` landmarks (those in the goal image) are usually all in view during an
    episode; the terms over all of them (``ok`` to ``pair_ok``) are kept, and recomputed
    only for the rows and steps where some of them are hidden.

    Attributes
    ----------
    x_goal
        ``(B, N, 2)`` goal points on the unit circle (``(1, 0)`` where hidden).
    seen
        ``(B, N)`` whether each landmark is in the goal image.
    d_goal
        ``(B, N)`` goal depths ``d*``, metres (1 where hidden or not positive).
    L_cx_all, L_cy_all
        ``(B, M)`` each: the ``v_x`` and ``v_y`` columns of ``L*_c`` (eq. 17) over every pair.
    c_goal
        ``(B, M)`` the goal image's ``c*_ij`` (eq. 12).
    ok, weights, L_alpha, L_cx, L_cy, normal, pair_ok
        Over the ``seen`` landmarks: whether there is an estimate ``(B,)``, the virtual
        point's weights ``(B, N)``, ``L*_alpha`` ``(B, 2)``, the masked ``L*_c`` columns
        ``(B, M)`` each, their normal matrix ``(B, 3)`` and the pairs used ``(B, M)``.
    """

    x_goal: F64
    seen: NDArray[np.bool_]
    d_goal: F64
    L_cx_all: F64
    L_cy_all: F64
    c_goal: F64
    ok: NDArray[np.bool_]
    weights: F64
    L_alpha: F64
    L_cx: F64
    L_cy: F64
    normal: F64
    pair_ok: NDArray[np.bool_]

    @classmethod
    def of(cls, goal_points: ArrayLike2, goal_depths: ArrayLike2) -> GoalTerms:
        """Compute the terms of ``(B, 2N)`` goal points and ``(B, N)`` goal depths (metres)."""
        x_goal = np.asarray(goal_points, dtype=np.float64)
        b = x_goal.shape[0]
        x_goal = x_goal.reshape(b, -1, 2)
        d_goal = np.asarray(goal_depths, dtype=np.float64).reshape(b, -1)
        norm = np.hypot(x_goal[..., 0], x_goal[..., 1])
        seen = norm > 0.5
        s3 = seen[..., None]
        x_goal = np.where(s3, x_goal / np.where(s3, norm[..., None], 1.0), np.array([1.0, 0.0]))
        d_goal = np.where(seen & (d_goal > 0), d_goal, 1.0)
        L_c_all = L_cij(x_goal, d_goal, np.zeros_like(d_goal))
        L_cx_all = np.ascontiguousarray(L_c_all[..., 0])
        L_cy_all = np.ascontiguousarray(L_c_all[..., 1])
        masked = _masked_goal(x_goal, d_goal, L_cx_all, L_cy_all, seen)
        return cls(x_goal, seen, d_goal, L_cx_all, L_cy_all, c_ij(x_goal), *masked)

    def take(self, rows: NDArray[np.intp], other: GoalTerms) -> None:
        """Replace ``rows`` with ``other``'s terms (one row of ``other`` per row index)."""
        for f in fields(self):
            getattr(self, f.name)[rows] = getattr(other, f.name)


class GoalCache:
    """The :class:`GoalTerms` of a batch, recomputed only for the rows whose goal changed.

    A residual env steps the same goal images for a whole episode; this keeps their terms
    from step to step, keyed by the goal points and depths themselves (a row whose goal
    arrays differ from the cached ones, e.g. after a reset, is recomputed), so the terms
    returned are always those of the goal given. One entry is kept per batch size (at most
    ``sizes``), so the small batches of an episode's last observations do not evict the
    training batch.
    """

    def __init__(self, sizes: int = 4) -> None:
        self.sizes = sizes
        self._entries: OrderedDict[int, tuple[F64, F64, GoalTerms]] = OrderedDict()

    def terms(self, goal_points: ArrayLike2, goal_depths: ArrayLike2) -> GoalTerms:
        """Return the terms of ``(B, 2N)`` goal points and ``(B, N)`` goal depths."""
        points = np.asarray(goal_points, dtype=np.float64)
        points = points.reshape(len(points), -1)
        depths = np.asarray(goal_depths, dtype=np.float64).reshape(len(points), -1)
        entry = self._entries.get(len(points))
        if entry is None or entry[0].shape != points.shape or entry[1].shape != depths.shape:
            terms = GoalTerms.of(points, depths)
            self._entries[len(points)] = (points.copy(), depths.copy(), terms)
            while len(self._entries) > self.sizes:
                self._entries.popitem(last=False)
            return terms
        self._entries.move_to_end(len(points))
        key_points, key_depths, terms = entry
        changed = np.flatnonzero(
            np.any(key_points != points, axis=1) | np.any(key_depths != depths, axis=1)
        )
        if len(changed):
            terms.take(changed, GoalTerms.of(points[changed], depths[changed]))
            key_points[changed], key_depths[changed] = points[changed], depths[changed]
        return terms


def ibvs_twist_batch(
    points: ArrayLike2,
    goal_points: ArrayLike2,
    goal_depths: ArrayLike2,
    visible: ArrayLike2,
    lam: float = 0.5,
    compensation: Literal["derived", "printed"] = "derived",
    frame_change: bool = True,
    goal: GoalTerms | None = None,
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
        Sign of eq. (30)'s compensation terms
        (:func:`radial_ibvs_agents.analytic.ibvs_maths.ibvs_twist`).
    frame_change
        Rotate ``v*`` into the current frame by ``gamma`` (eq. 36-37); ``False`` is the
        ``no-frame-change`` variant, ``v = -v*``.
    goal
        The goal's terms, if already computed (:class:`GoalCache`); they must be those of
        ``goal_points`` and ``goal_depths``. ``None``: computed here.

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
    if goal is None:
        goal = GoalTerms.of(goal_points, goal_depths)
    x_now = np.asarray(points, dtype=np.float64)
    b = x_now.shape[0]
    x_now = x_now.reshape(b, -1, 2)
    norm_now = np.hypot(x_now[..., 0], x_now[..., 1])
    mask = (np.asarray(visible, dtype=np.float64).reshape(b, -1) > 0.5) & (norm_now > 0.5)
    mask &= goal.seen
    m3 = mask[..., None]
    x_now = np.where(m3, x_now / np.where(m3, norm_now[..., None], 1.0), np.array([1.0, 0.0]))
    # the goal-side terms over the landmarks in view: the episode's, unless some are hidden
    ok, weights, L_alpha = goal.ok, goal.weights, goal.L_alpha
    L_cx, L_cy, normal, pair_ok = goal.L_cx, goal.L_cy, goal.normal, goal.pair_ok
    hidden = np.flatnonzero(np.any(mask != goal.seen, axis=1))
    if len(hidden):
        rows = _masked_goal(
            goal.x_goal[hidden], goal.d_goal[hidden], goal.L_cx_all[hidden],
            goal.L_cy_all[hidden], mask[hidden],
        )  # fmt: skip
        terms: list[NDArray[Any]] = [
            np.array(t) for t in (ok, weights, L_alpha, L_cx, L_cy, normal, pair_ok)
        ]
        for full, part in zip(terms, rows, strict=True):
            full[hidden] = part
        ok, weights, L_alpha, L_cx, L_cy, normal, pair_ok = terms
    # eq. (12), (30): v* = -lambda pinv(L*_c) (c - c*) over the pairs in view
    error = np.where(pair_ok, goal.c_goal - c_ij(x_now), 0.0)  # c* - c
    r0 = np.sum(L_cx * error, axis=-1)
    r1 = np.sum(L_cy * error, axis=-1)
    p0, p1, rank2 = _solve_2x2(normal[:, 0], normal[:, 1], normal[:, 2], r0, r1)
    ok = ok & rank2
    v_star = -lam * np.stack([p0, p1], axis=-1)
    # eq. (24)-(26), (30), (37): alpha_m and gamma
    p_now = np.sum(weights[..., None] * x_now, axis=-2)
    error_alpha = wrap_angle(-np.arctan2(p_now[:, 1], p_now[:, 0]))  # alpha*_m = 0
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
    """Robot speeds from eq. (38) for a batch (``ibvs_maths.park_command``, batched).

    Parameters
    ----------
    v
        ``(B, 2)`` camera velocities in the current frame, m/s.
    gamma
        ``(B,)`` estimated rotations to the goal orientation, radians.
    lam, k1, k2, v_max, omega_max, stop_radius, stop_heading, rotate_radius, allow_backward
        As in :func:`~radial_ibvs_agents.analytic.ibvs_maths.park_command` (1/s, m/s, rad/s, metres,
        radians).

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
