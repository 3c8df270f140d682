"""The feature errors of the paper's IBVS, one home for the scalar and the vector envs.

``c*_ij - c_ij`` and ``alpha_m* - alpha_m`` (eq. 12, 19-29) of ``B`` episodes against their goal
images (:class:`FeatureErrors`; one episode is ``B = 1``), the goal's virtual-point weights
computed once per visibility mask and episode (:func:`goal_weights`). Pure numpy.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from radial_ibvs_gym.features import c_ij, virtual_point_weights
from radial_ibvs_gym.geometry import wrap_angle

__all__ = ["FeatureErrors", "feature_errors", "goal_weights", "unit_or_dummy"]

Array = NDArray[np.float64]


def unit_or_dummy(points: Array, mask: NDArray[np.bool_]) -> Array:
    """Hidden points (zeros) replaced by ``(1, 0)``: the features need unit vectors.

    The pairs with a hidden point are masked out afterwards.
    """
    return np.where(mask[..., None], points, np.array([1.0, 0.0]))


def goal_weights(goal_points: Array, mask: NDArray[np.bool_]) -> Array | None:
    """Virtual-point weights (eq. 27-29) of the goal points in ``mask``, as an ``(N,)`` vector.

    Zero outside ``mask``; ``None`` when fewer than 2 points are in it or they are collinear
    with the axis (no virtual point).
    """
    if mask.sum() < 2:
        return None
    try:
        a = virtual_point_weights(goal_points[mask])
    except ValueError:  # goal points collinear with the axis: no virtual point
        return None
    full = np.zeros(mask.shape, dtype=np.float64)
    full[mask] = a
    return full


def feature_errors(
    points: Array,
    both: NDArray[np.bool_],
    c_goal: Array,
    pairs: tuple[NDArray[np.intp], NDArray[np.intp]],
    weights: Array,
    has_weights: Any,
) -> tuple[Array, Array]:
    """Feature errors ``c*_ij - c_ij`` and ``alpha_m* - alpha_m`` (eq. 12, 19-29).

    Parameters
    ----------
    points
        ``(..., N, 2)`` current image points (zeros where hidden).
    both
        ``(..., N)`` visible now and in the goal image.
    c_goal
        ``(..., M)`` the goal image's ``c*_ij``.
    pairs
        The ``(i, j)`` index arrays of the ``M`` pairs.
    weights
        ``(..., N)`` the goal's virtual-point weights over ``both`` (:func:`goal_weights`; zero
        outside ``both``).
    has_weights
        ``(...)`` whether a virtual point exists (else ``alpha_m`` error is 0).

    Returns
    -------
    c_error
        ``(..., M)``, 0 for pairs with a point not in ``both``.
    alpha_m_error
        ``(..., 1)`` radians: the goal's virtual point is ``(1, 0)`` by construction, so the
        error is ``-alpha_m`` of the current virtual point ``sum_i a_i x_ni``.
    """
    i, j = pairs
    pair_ok = both[..., i] & both[..., j]
    c_now = c_ij(unit_or_dummy(points, both))
    c_err = np.where(pair_ok, c_goal - c_now, 0.0)
    p_now = (weights[..., None] * points).sum(axis=-2)
    alpha = np.where(has_weights, wrap_angle(-np.arctan2(p_now[..., 1], p_now[..., 0])), 0.0)
    return c_err, alpha[..., None]


class FeatureErrors:
    """The feature errors of ``B`` episodes, each against its own goal image.

    Holds each episode's ``c*_ij`` and the goal's virtual-point weights over the landmarks
    visible now and in the goal image; the weights are computed once per visibility mask and
    episode (they depend on the goal image and the mask only). The scalar env holds one
    (``B = 1``), the native vector env one row per env: the same code, the same bits.

    Parameters
    ----------
    b
        The episodes ``B``.
    n
        The landmarks ``N`` of each.
    pairs
        The ``(i, j)`` index arrays of the ``M`` pairs.
    """

    def __init__(self, b: int, n: int, pairs: tuple[NDArray[np.intp], NDArray[np.intp]]) -> None:
        self.pairs = pairs
        self.c_goal = np.zeros((b, len(pairs[0])))
        self.weights = np.zeros((b, n))
        self.has_weights = np.zeros(b, dtype=bool)
        self.both = np.zeros((b, n), dtype=bool)
        self._goal_points = np.zeros((b, n, 2))
        self._caches: list[dict[bytes, Array | None]] = [{} for _ in range(b)]

    def start(self, row: int, c_goal: Array, goal_points: Array) -> None:
        """Start episode ``row``: its goal image's ``c*_ij`` ``(M,)`` and points ``(N, 2)``."""
        self.c_goal[row] = c_goal
        self._goal_points[row] = goal_points
        self._caches[row] = {}
        self.both[row] = False
        self.weights[row] = 0.0
        self.has_weights[row] = False

    def update(self, rows: NDArray[np.intp], both: NDArray[np.bool_]) -> None:
        """Take the landmarks ``both`` ``(k, N)`` visible now and in the goal of ``rows``."""
        changed = (both != self.both[rows]).any(axis=1)
        for k in np.flatnonzero(changed).tolist():
            i = int(rows[k])
            key = both[k].tobytes()
            cache = self._caches[i]
            if key not in cache:
                cache[key] = goal_weights(self._goal_points[i], both[k])
            a = cache[key]
            self.has_weights[i] = a is not None
            self.weights[i] = 0.0 if a is None else a
        self.both[rows] = both

    def errors(self, points: Array, rows: Any = slice(None)) -> tuple[Array, Array]:
        """Return ``c_error`` ``(k, M)`` and ``alpha_m_error`` ``(k, 1)`` of ``rows``.

        ``points`` ``(k, N, 2)``: the rows' current image points (zeros where hidden).
        """
        return feature_errors(
            points,
            self.both[rows],
            self.c_goal[rows],
            self.pairs,
            self.weights[rows],
            self.has_weights[rows],
        )
