"""All the features of the paper's controller for one scene or a batch, in one call."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from radial_ibvs_gym.features._checks import check_scene, check_sign, check_weights
from radial_ibvs_gym.features.pairs import L_cij, c_ij
from radial_ibvs_gym.features.virtual_point import L_alpha_m, alpha_m

__all__ = ["Features", "compute_features"]


class Features(NamedTuple):
    """The visual features of Section 3 and their interaction matrices.

    Attributes
    ----------
    c
        ``(..., M)`` pairwise inner products ``c_ij`` (eq. 12), ``M = N (N - 1) / 2``, in the
        order of :func:`~radial_ibvs_gym.features.pair_indices`.
    L_c
        ``(..., M, 6)`` their interaction matrices (eq. 17-18).
    alpha_m
        ``(...)`` angle of the virtual point in radians (eq. 25).
    L_alpha_m
        ``(..., 6)`` its interaction matrix (eq. 24, 26).
    """

    c: NDArray[np.float64]
    L_c: NDArray[np.float64]
    alpha_m: NDArray[np.float64]
    L_alpha_m: NDArray[np.float64]


def compute_features(
    x_n: ArrayLike, d: ArrayLike, z_n: ArrayLike, a: ArrayLike, *, sign: int = 1
) -> Features:
    """Compute ``c_ij``, ``L_cij``, ``alpha_m`` and ``L_alpha_m`` together.

    Parameters
    ----------
    x_n
        ``(..., N, 2)`` image points on the unit circle (eq. 9), ``N >= 2``.
    d
        ``(..., N)`` horizontal distances in metres, > 0 (the current ones for the exact
        matrices, the goal ones for the paper's ``L*``).
    z_n
        ``(..., N)`` ratios ``Z / d``.
    a
        ``(..., N)`` virtual-point weights from the goal image
        (:func:`~radial_ibvs_gym.features.virtual_point_weights`); leading dimensions broadcast
        with those of ``x_n``.
    sign
        Radial sign of the mirror (+1 convex, -1 concave).

    Returns
    -------
    Features
        Named tuple ``(c, L_c, alpha_m, L_alpha_m)`` with the shapes documented there.

    Raises
    ------
    ValueError
        For any degenerate input (see :func:`~radial_ibvs_gym.features.L_cij` and
        :func:`~radial_ibvs_gym.features.L_alpha_m`).
    """
    s = check_sign(sign)
    x, dd, zz = check_scene(x_n, d, z_n, min_points=2)
    w = check_weights(a, x)
    return Features(
        c=c_ij(x),
        L_c=L_cij(x, dd, zz, sign=s),
        alpha_m=alpha_m(x, w),
        L_alpha_m=L_alpha_m(x, dd, zz, w, sign=s),
    )
