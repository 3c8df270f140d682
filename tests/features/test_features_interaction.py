"""Every interaction matrix of the features layer against central finite differences.

For each of the 6 unit camera twists the scene is moved exactly along ``exp(t tau)``
(``apply_twist_to_points``, ``t = +-h, +-2h``) and the feature's central difference is
compared with the corresponding column of the analytic matrix: all 6 columns, including
``v_z``, ``omega_x`` and ``omega_y``, for both radial signs. Error: ``|L - L_fd|`` over
``max(|L_fd|, 1e-3)``, entrywise, below 1e-6.
"""

from __future__ import annotations

from collections.abc import Callable

import hypothesis.extra.numpy as hnp
import numpy as np
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from numpy.typing import NDArray

from radial_ibvs_gym.camera.radial import RadialPoints, radial_points
from radial_ibvs_gym.features import (
    L_alpha,
    L_alpha_m,
    L_cij,
    L_xn,
    alpha,
    alpha_m,
    c_ij,
    virtual_point,
    virtual_point_weights,
)
from radial_ibvs_gym.geometry import apply_twist_to_points, wrap_angle

STEP = 1e-5  # metres / radians
FLOOR = 1e-3  # absolute floor of the relative error, for entries that are (nearly) zero
TOL = 1e-6
SETTINGS = settings(max_examples=200, deadline=None)

signs = st.sampled_from([1, -1])


@st.composite
def scene_points(draw: st.DrawFn, n: int) -> NDArray[np.float64]:
    """``(n, 3)`` points: horizontal distance in [0.5, 15] m, height in [-2, 2] m."""
    d = draw(hnp.arrays(np.float64, n, elements=st.floats(0.5, 15.0)))
    az = draw(hnp.arrays(np.float64, n, elements=st.floats(-np.pi, np.pi)))
    z = draw(hnp.arrays(np.float64, n, elements=st.floats(-2.0, 2.0)))
    return np.stack([d * np.cos(az), d * np.sin(az), z], axis=-1)


@st.composite
def scenes(draw: st.DrawFn, min_n: int = 2, max_n: int = 12) -> NDArray[np.float64]:
    return draw(scene_points(draw(st.integers(min_n, max_n))))


def finite_difference(
    feature: Callable[[RadialPoints], NDArray[np.float64]],
    points: NDArray[np.float64],
    sign: int,
    angle: bool = False,
) -> NDArray[np.float64]:
    """``(..., 6)``: central differences of ``feature`` along the 6 unit twists.

    The symmetric 5-point stencil ``(8 (f(h) - f(-h)) - (f(2h) - f(-2h))) / 12h``: the plain
    3-point one has an O(h^2) error of ~3e-9 where two points share a direction (c_ij = 1, a
    maximum, where L_cij = 0 exactly), which no small absolute floor absorbs.
    """
    twists = np.eye(6)
    stacked = np.broadcast_to(points, (6, *points.shape))

    def diff(step: float) -> NDArray[np.float64]:
        plus = feature(radial_points(apply_twist_to_points(stacked, twists, step), sign))
        minus = feature(radial_points(apply_twist_to_points(stacked, twists, -step), sign))
        return wrap_angle(plus - minus) if angle else plus - minus

    derivative = (8.0 * diff(STEP) - diff(2.0 * STEP)) / (12.0 * STEP)
    return np.moveaxis(derivative, 0, -1)


def relative_error(analytic: NDArray[np.float64], numeric: NDArray[np.float64]) -> float:
    assert analytic.shape == numeric.shape
    return float(np.max(np.abs(analytic - numeric) / np.maximum(np.abs(numeric), FLOOR)))


@SETTINGS
@given(points=scenes(), sign=signs)
def test_L_xn_matches_finite_differences(points: NDArray[np.float64], sign: int) -> None:
    rp = radial_points(points, sign)
    numeric = finite_difference(lambda r: r.x_n, points, sign)
    analytic = L_xn(rp.x_n, rp.d, rp.z_n, sign=sign)
    assert analytic.shape == (len(points), 2, 6)
    assert relative_error(analytic, numeric) < TOL


@SETTINGS
@given(points=scenes(), sign=signs)
def test_L_cij_matches_finite_differences(points: NDArray[np.float64], sign: int) -> None:
    rp = radial_points(points, sign)
    numeric = finite_difference(lambda r: c_ij(r.x_n), points, sign)
    analytic = L_cij(rp.x_n, rp.d, rp.z_n, sign=sign)
    n = len(points)
    assert analytic.shape == (n * (n - 1) // 2, 6)
    assert relative_error(analytic, numeric) < TOL


@SETTINGS
@given(points=scenes(), sign=signs)
def test_L_alpha_matches_finite_differences(points: NDArray[np.float64], sign: int) -> None:
    rp = radial_points(points, sign)
    numeric = finite_difference(lambda r: alpha(r.x_n), points, sign, angle=True)
    analytic = L_alpha(rp.x_n, rp.d, rp.z_n, sign=sign)
    assert analytic.shape == (len(points), 6)
    assert relative_error(analytic, numeric) < TOL


@st.composite
def goal_and_current(draw: st.DrawFn) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """A goal scene and the same points seen after a random camera displacement."""
    n = draw(st.integers(3, 12))
    goal = draw(scene_points(n))
    v = draw(hnp.arrays(np.float64, 3, elements=st.floats(-2.0, 2.0)))
    w = draw(hnp.arrays(np.float64, 3, elements=st.floats(-np.pi, np.pi)))
    w[:2] *= 0.2  # tilts up to ~0.6 rad, any yaw
    current = apply_twist_to_points(goal, np.concatenate([v, w]), 1.0)
    return goal, current


@SETTINGS
@given(scenes_=goal_and_current(), sign=signs)
def test_L_alpha_m_matches_finite_differences(
    scenes_: tuple[NDArray[np.float64], NDArray[np.float64]], sign: int
) -> None:
    goal, current = scenes_
    assume(np.min(np.hypot(current[:, 0], current[:, 1])) > 0.3)
    x_goal = radial_points(goal, sign).x_n
    sv = np.linalg.svd(x_goal, compute_uv=False)
    assume(sv[1] > 0.05 * sv[0])  # not (nearly) all goal points on one line through the axis
    a = virtual_point_weights(x_goal)  # fixed while the camera moves
    rp = radial_points(current, sign)
    assume(np.linalg.norm(virtual_point(rp.x_n, a)) > 0.05)
    numeric = finite_difference(lambda r: alpha_m(r.x_n, a), current, sign, angle=True)
    analytic = L_alpha_m(rp.x_n, rp.d, rp.z_n, a, sign=sign)
    assert analytic.shape == (6,)
    assert relative_error(analytic, numeric) < TOL
