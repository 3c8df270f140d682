"""Degenerate inputs raise ValueError with a message naming the problem and the value."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

from radial_ibvs_gym.camera.radial import radial_points
from radial_ibvs_gym.features import (
    L_alpha,
    L_alpha_m,
    L_cij,
    L_xn,
    alpha,
    alpha_m,
    c_ij,
    compute_features,
    pair_indices,
    planar,
    virtual_point,
    virtual_point_weights,
)

POINTS = np.array([[2.0, 0.0, 0.5], [0.0, 3.0, -1.0], [-1.0, -1.0, 0.2], [4.0, -2.0, 1.0]])
RP = radial_points(POINTS)
X, D, Z = RP.x_n, RP.d, RP.z_n
A = virtual_point_weights(X)

SCENE_FUNCTIONS: dict[str, Callable[..., Any]] = {
    "L_xn": L_xn,
    "L_alpha": L_alpha,
    "L_cij": L_cij,
    "L_alpha_m": lambda x, d, z: L_alpha_m(x, d, z, A),
    "compute_features": lambda x, d, z: compute_features(x, d, z, A),
}
POINT_FUNCTIONS: dict[str, Callable[..., Any]] = {
    "alpha": alpha,
    "c_ij": c_ij,
    "virtual_point": lambda x: virtual_point(x, A),
    "alpha_m": lambda x: alpha_m(x, A),
    "virtual_point_weights": virtual_point_weights,
    **{name: (lambda x, f=f: f(x, D, Z)) for name, f in SCENE_FUNCTIONS.items()},
}


@pytest.mark.parametrize("name", sorted(SCENE_FUNCTIONS))
def test_point_on_the_optical_axis(name: str) -> None:
    d = D.copy()
    d[2] = 0.0
    with pytest.raises(ValueError, match=r"d\[2\] = 0\.0 is not positive.*optical axis"):
        SCENE_FUNCTIONS[name](X, d, Z)
    d[2] = -1.5
    with pytest.raises(ValueError, match=r"d\[2\] = -1\.5 is not positive"):
        SCENE_FUNCTIONS[name](X, d, Z)


@pytest.mark.parametrize("name", sorted(POINT_FUNCTIONS))
@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_non_finite_points(name: str, bad: float) -> None:
    x = X.copy()
    x[1, 0] = bad
    with pytest.raises(ValueError, match=r"must be finite, got .*(nan|inf).* at index \(1, 0\)"):
        POINT_FUNCTIONS[name](x)


@pytest.mark.parametrize("name", sorted(SCENE_FUNCTIONS))
@pytest.mark.parametrize("which", ["d", "z_n"])
def test_non_finite_depths(name: str, which: str) -> None:
    d, z = D.copy(), Z.copy()
    (d if which == "d" else z)[3] = np.nan
    with pytest.raises(ValueError, match=rf"{which} must be finite, got .*nan.* at index \(3,\)"):
        SCENE_FUNCTIONS[name](X, d, z)


@pytest.mark.parametrize("name", sorted(POINT_FUNCTIONS))
def test_points_off_the_unit_circle(name: str) -> None:
    x = X.copy()
    x[2] *= 1.01
    with pytest.raises(ValueError, match=r"\[2\] = .* is not of unit norm \(\|x_n\| = 1\.01,"):
        POINT_FUNCTIONS[name](x)


def test_unit_norm_tolerance_is_1e_6() -> None:
    x = X.copy()
    x[0] *= 1.0 + 5e-7
    L_xn(x, D, Z)
    x[0] *= 1.0 + 1e-6
    with pytest.raises(ValueError, match="not of unit norm"):
        L_xn(x, D, Z)


@pytest.mark.parametrize(
    "name",
    ["c_ij", "virtual_point", "alpha_m", "virtual_point_weights", "L_cij", "L_alpha_m"],
)
def test_fewer_than_two_points(name: str) -> None:
    with pytest.raises(ValueError, match=r"has 1 point\(s\).*at least 2 points"):
        POINT_FUNCTIONS[name](X[:1])


def test_single_point_is_fine_for_per_point_features() -> None:
    assert L_xn(X[:1], D[:1], Z[:1]).shape == (1, 2, 6)
    assert L_alpha(X[:1], D[:1], Z[:1]).shape == (1, 6)
    assert alpha(X[:1]).shape == (1,)
    with pytest.raises(ValueError, match=r"has 0 point\(s\)"):
        alpha(X[:0])


@pytest.mark.parametrize("n", [0, 1, -3])
def test_pair_indices_needs_two_points(n: int) -> None:
    with pytest.raises(ValueError, match=rf"n = {n}: at least 2 points"):
        pair_indices(n)


def test_pair_indices_needs_an_integer() -> None:
    with pytest.raises(ValueError, match=r"integer number of points, got 2\.5"):
        pair_indices(2.5)  # type: ignore[arg-type]


@pytest.mark.parametrize("name", sorted(SCENE_FUNCTIONS))
def test_mismatched_shapes(name: str) -> None:
    f = SCENE_FUNCTIONS[name]
    with pytest.raises(
        ValueError, match=r"d must have shape x_n.shape\[:-1\] = \(4,\), got shape \(3,\)"
    ):
        f(X, D[:3], Z)
    with pytest.raises(ValueError, match=r"z_n must have shape .* got shape \(2, 4\)"):
        f(X, D, np.stack([Z, Z]))
    with pytest.raises(ValueError, match=r"x_n must have shape \(\.\.\., 2\), got shape \(4, 3\)"):
        f(POINTS, D, Z)
    with pytest.raises(ValueError, match=r"x_n must have shape \(\.\.\., N, 2\), got shape \(2,\)"):
        f(X[0], D[0], Z[0])


@pytest.mark.parametrize(
    "call",
    [
        lambda a: virtual_point(X, a),
        lambda a: alpha_m(X, a),
        lambda a: L_alpha_m(X, D, Z, a),
        lambda a: compute_features(X, D, Z, a),
    ],
)
def test_weights_of_the_wrong_shape(call: Callable[[Any], Any]) -> None:
    with pytest.raises(ValueError, match=r"a must have shape \(\.\.\., N\) with N = 4"):
        call(A[:3])
    with pytest.raises(
        ValueError, match=r"a must have shape \(\.\.\., N\) with N = 4 .* got shape \(\)"
    ):
        call(1.0)


def test_weights_batch_must_broadcast() -> None:
    x = np.stack([X, X])  # batch (2,)
    with pytest.raises(ValueError, match=r"batch shape of a \(3,\) does not broadcast .* \(2,\)"):
        alpha_m(x, np.stack([A, A, A]))
    assert alpha_m(x, A).shape == (2,)
    assert alpha_m(x, np.stack([A, A])).shape == (2,)


def test_non_finite_weights() -> None:
    a = A.copy()
    a[0] = np.nan
    with pytest.raises(ValueError, match=r"a must be finite"):
        alpha_m(X, a)


@pytest.mark.parametrize("u", [(1.0, 0.0), (0.6, -0.8)])
def test_goal_points_collinear_with_the_axis(u: tuple[float, float]) -> None:
    # every goal point in one vertical plane through the axis: x*_n = +-u
    x_goal = np.array([u, (-u[0], -u[1]), u, u])
    with pytest.raises(ValueError, match=r"goal image x_n_goal\[\] is degenerate: .*rank < 2"):
        virtual_point_weights(x_goal)
    batch = np.stack([X, x_goal])
    with pytest.raises(ValueError, match=r"goal image x_n_goal\[1\] is degenerate"):
        virtual_point_weights(batch)


@pytest.mark.parametrize("p1_star", [(2.0, 0.0), (0.0, 0.0), (0.7, 0.7)])
def test_p1_star_must_be_unit(p1_star: tuple[float, float]) -> None:
    with pytest.raises(ValueError, match=r"p1_star must be a unit vector, got \["):
        virtual_point_weights(X, p1_star)


def test_p1_star_must_be_finite_and_2d() -> None:
    with pytest.raises(ValueError, match=r"p1_star must be finite"):
        virtual_point_weights(X, (np.nan, 1.0))
    with pytest.raises(ValueError, match=r"p1_star must have shape \(\.\.\., 2\)"):
        virtual_point_weights(X, (1.0, 0.0, 0.0))


def test_virtual_point_of_zero_norm() -> None:
    # two opposite points with equal weights: p1 = 0
    x = np.array([[1.0, 0.0], [-1.0, 0.0]])
    d, z, a = np.ones(2), np.zeros(2), np.array([0.5, 0.5])
    np.testing.assert_array_equal(virtual_point(x, a), [0.0, 0.0])  # defined, just zero
    for call in (lambda: alpha_m(x, a), lambda: L_alpha_m(x, d, z, a)):
        with pytest.raises(ValueError, match=r"virtual point p1\[\] = \[0\.0, 0\.0\] has norm 0 <"):
            call()
    with pytest.raises(ValueError, match=r"virtual point p1\[1\] = .* has norm"):
        alpha_m(np.stack([X[:2], x]), np.stack([A[:2], a]))


@pytest.mark.parametrize("sign", [0, 2, -2, True, 1.5])
def test_bad_sign(sign: Any) -> None:
    with pytest.raises(ValueError, match=r"sign must be \+1 or -1, got"):
        L_xn(X, D, Z, sign=sign)
    with pytest.raises(ValueError, match=r"sign must be \+1 or -1"):
        compute_features(X, D, Z, A, sign=sign)


def test_non_numeric_input() -> None:
    with pytest.raises(ValueError, match=r"x_n must be numeric"):
        c_ij([["a", "b"], ["c", "d"]])


def test_planar_needs_six_columns() -> None:
    with pytest.raises(ValueError, match=r"L must have shape \(\.\.\., 6\), got shape \(4, 3\)"):
        planar(np.zeros((4, 3)))
