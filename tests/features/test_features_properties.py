"""Structural properties of the features: invariances, zero columns, the goal, batching."""

from __future__ import annotations

import hypothesis.extra.numpy as hnp
import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from numpy.typing import NDArray

from radial_ibvs_gym.camera.radial import radial_points
from radial_ibvs_gym.features import (
    PLANAR_COLUMNS,
    Features,
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
from radial_ibvs_gym.geometry import apply_twist_to_points, rot_z, wrap_angle

SETTINGS = settings(max_examples=100, deadline=None)
angles = st.floats(-np.pi, np.pi)


@st.composite
def scenes(draw: st.DrawFn, min_n: int = 2, max_n: int = 12) -> NDArray[np.float64]:
    n = draw(st.integers(min_n, max_n))
    d = draw(hnp.arrays(np.float64, n, elements=st.floats(0.5, 15.0)))
    az = draw(hnp.arrays(np.float64, n, elements=angles))
    z = draw(hnp.arrays(np.float64, n, elements=st.floats(-2.0, 2.0)))
    return np.stack([d * np.cos(az), d * np.sin(az), z], axis=-1)


def random_scenes(rng: np.random.Generator, shape: tuple[int, ...]) -> NDArray[np.float64]:
    d = rng.uniform(0.5, 15.0, shape)
    az = rng.uniform(-np.pi, np.pi, shape)
    return np.stack([d * np.cos(az), d * np.sin(az), rng.uniform(-2, 2, shape)], axis=-1)


def well_posed_weights(x_goal: NDArray[np.float64]) -> NDArray[np.float64]:
    sv = np.linalg.svd(x_goal, compute_uv=False)
    assume(sv[1] > 0.05 * sv[0])
    return virtual_point_weights(x_goal)


# --- pair order --------------------------------------------------------------------------------


@pytest.mark.parametrize("n", [2, 3, 5, 12])
def test_pair_indices_are_row_major_upper_triangle(n: int) -> None:
    i, j = pair_indices(n)
    expected = [(a, b) for a in range(n) for b in range(a + 1, n)]
    assert list(zip(i.tolist(), j.tolist(), strict=True)) == expected
    x = radial_points(random_scenes(np.random.default_rng(n), (n,))).x_n
    np.testing.assert_allclose(c_ij(x), [x[a] @ x[b] for a, b in expected], atol=1e-15)


# --- eq. (35): c_ij is invariant to a rotation about z; alpha_m turns with it ------------------


@SETTINGS
@given(points=scenes(), gamma=angles)
def test_c_ij_is_invariant_to_a_rotation_about_the_axis(
    points: NDArray[np.float64], gamma: float
) -> None:
    rotated = points @ rot_z(gamma).T
    np.testing.assert_allclose(
        c_ij(radial_points(rotated).x_n), c_ij(radial_points(points).x_n), rtol=0, atol=1e-12
    )


@SETTINGS
@given(goal=scenes(min_n=3), gamma=angles, sign=st.sampled_from([1, -1]))
def test_alpha_m_turns_by_minus_the_camera_rotation(
    goal: NDArray[np.float64], gamma: float, sign: int
) -> None:
    rp = radial_points(goal, sign)
    a = well_posed_weights(rp.x_n)
    assume(np.linalg.norm(virtual_point(rp.x_n, a)) > 1e-3)
    turned = apply_twist_to_points(goal, [0, 0, 0, 0, 0, 1.0], gamma)  # camera turns by gamma
    change = wrap_angle(alpha_m(radial_points(turned, sign).x_n, a) - alpha_m(rp.x_n, a))
    assert abs(wrap_angle(change + gamma)) < 1e-12
    # and every point angle turns by -gamma too (eq. 21's -1)
    point_change = wrap_angle(alpha(radial_points(turned, sign).x_n) - alpha(rp.x_n))
    np.testing.assert_allclose(wrap_angle(point_change + gamma), 0.0, atol=1e-12)


@SETTINGS
@given(goal=scenes(min_n=3), current=scenes(min_n=12, max_n=12), sign=st.sampled_from([1, -1]))
def test_L_alpha_m_omega_z_is_minus_one_everywhere(
    goal: NDArray[np.float64], current: NDArray[np.float64], sign: int
) -> None:
    a = well_posed_weights(radial_points(goal, sign).x_n)
    rp = radial_points(current[: len(goal)], sign)
    assume(np.linalg.norm(virtual_point(rp.x_n, a)) > 1e-3)
    L = L_alpha_m(rp.x_n, rp.d, rp.z_n, a, sign=sign)
    assert abs(L[5] + 1.0) < 1e-12


# --- zero columns ------------------------------------------------------------------------------


@SETTINGS
@given(points=scenes(), sign=st.sampled_from([1, -1]))
def test_zero_columns(points: NDArray[np.float64], sign: int) -> None:
    rp = radial_points(points, sign)
    Lc = L_cij(rp.x_n, rp.d, rp.z_n, sign=sign)
    assert np.all(Lc[..., 2] == 0.0)  # v_z
    assert np.all(Lc[..., 5] == 0.0)  # omega_z
    assert np.all(L_xn(rp.x_n, rp.d, rp.z_n, sign=sign)[..., 2] == 0.0)  # v_z
    La = L_alpha(rp.x_n, rp.d, rp.z_n, sign=sign)
    assert np.all(La[..., 2] == 0.0)
    assert np.all(La[..., 5] == -1.0)


# --- the goal ----------------------------------------------------------------------------------


@SETTINGS
@given(goal=scenes(), phi=angles)
def test_virtual_point_of_the_goal_is_p1_star(goal: NDArray[np.float64], phi: float) -> None:
    x_goal = radial_points(goal).x_n
    p1_star = np.array([np.cos(phi), np.sin(phi)])
    sv = np.linalg.svd(x_goal, compute_uv=False)
    assume(sv[1] > 1e-3 * sv[0])
    a = virtual_point_weights(x_goal, p1_star)
    assert a.shape == (len(goal),)
    np.testing.assert_allclose(virtual_point(x_goal, a), p1_star, rtol=0, atol=1e-10)
    assert abs(wrap_angle(alpha_m(x_goal, a) - np.arctan2(p1_star[1], p1_star[0]))) < 1e-10


def test_virtual_point_of_the_goal_default_and_minimum_norm() -> None:
    x_goal = radial_points(random_scenes(np.random.default_rng(3), (7,))).x_n
    a = virtual_point_weights(x_goal)
    np.testing.assert_allclose(virtual_point(x_goal, a), [1.0, 0.0], atol=1e-14)
    assert alpha_m(x_goal, a) == pytest.approx(0.0, abs=1e-14)
    # the first column of pinv(B) is also the minimum-norm solution of X*_nt a = p1*
    np.testing.assert_allclose(a, np.linalg.pinv(x_goal.T) @ [1.0, 0.0], atol=1e-12)


def test_two_goal_points_suffice() -> None:
    x_goal = np.array([[1.0, 0.0], [0.0, 1.0]])
    a = virtual_point_weights(x_goal, (0.0, 1.0))
    np.testing.assert_allclose(a, [0.0, 1.0], atol=1e-15)


# --- batching ----------------------------------------------------------------------------------


@pytest.mark.parametrize("sign", [1, -1])
def test_batched_results_equal_per_scene_results(sign: int) -> None:
    rng = np.random.default_rng(7)
    points = random_scenes(rng, (5, 4, 6))  # (5, 4) scenes of 6 points
    rp = radial_points(points, sign)
    goals = radial_points(random_scenes(rng, (5, 4, 6)), sign).x_n
    a = virtual_point_weights(goals)  # one goal per scene
    a_shared = a[0, 0]  # one goal for the whole batch
    batched = {
        "L_xn": L_xn(rp.x_n, rp.d, rp.z_n, sign=sign),
        "alpha": alpha(rp.x_n),
        "L_alpha": L_alpha(rp.x_n, rp.d, rp.z_n, sign=sign),
        "c": c_ij(rp.x_n),
        "L_c": L_cij(rp.x_n, rp.d, rp.z_n, sign=sign),
        "alpha_m": alpha_m(rp.x_n, a),
        "L_alpha_m": L_alpha_m(rp.x_n, rp.d, rp.z_n, a, sign=sign),
        "shared": L_alpha_m(rp.x_n, rp.d, rp.z_n, a_shared, sign=sign),
        "p1": virtual_point(rp.x_n, a),
    }
    features = compute_features(rp.x_n, rp.d, rp.z_n, a, sign=sign)
    assert batched["L_xn"].shape == (5, 4, 6, 2, 6)
    assert batched["L_c"].shape == (5, 4, 15, 6)
    assert batched["L_alpha_m"].shape == (5, 4, 6)
    assert features.c.shape == (5, 4, 15) and features.alpha_m.shape == (5, 4)
    for b in range(5):
        for k in range(4):
            x, d, z = rp.x_n[b, k], rp.d[b, k], rp.z_n[b, k]
            one = {
                "L_xn": L_xn(x, d, z, sign=sign),
                "alpha": alpha(x),
                "L_alpha": L_alpha(x, d, z, sign=sign),
                "c": c_ij(x),
                "L_c": L_cij(x, d, z, sign=sign),
                "alpha_m": alpha_m(x, a[b, k]),
                "L_alpha_m": L_alpha_m(x, d, z, a[b, k], sign=sign),
                "shared": L_alpha_m(x, d, z, a_shared, sign=sign),
                "p1": virtual_point(x, a[b, k]),
            }
            np.testing.assert_allclose(virtual_point_weights(goals[b, k]), a[b, k], atol=1e-12)
            for name, value in one.items():
                np.testing.assert_allclose(batched[name][b, k], value, rtol=1e-13, atol=1e-13)
            single = compute_features(x, d, z, a[b, k], sign=sign)
            for field in Features._fields:
                np.testing.assert_allclose(
                    getattr(features, field)[b, k], getattr(single, field), atol=1e-13
                )


def test_compute_features_matches_the_individual_functions() -> None:
    rp = radial_points(random_scenes(np.random.default_rng(11), (8,)))
    a = virtual_point_weights(radial_points(random_scenes(np.random.default_rng(12), (8,))).x_n)
    f = compute_features(rp.x_n, rp.d, rp.z_n, a)
    assert isinstance(f, Features)
    np.testing.assert_array_equal(f.c, c_ij(rp.x_n))
    np.testing.assert_array_equal(f.L_c, L_cij(rp.x_n, rp.d, rp.z_n))
    np.testing.assert_array_equal(f.alpha_m, alpha_m(rp.x_n, a))
    np.testing.assert_array_equal(f.L_alpha_m, L_alpha_m(rp.x_n, rp.d, rp.z_n, a))


# --- planar ------------------------------------------------------------------------------------


def test_planar_keeps_v_x_v_y_omega_z() -> None:
    L = np.arange(2 * 3 * 6, dtype=float).reshape(2, 3, 6)
    out = planar(L)
    assert PLANAR_COLUMNS == (0, 1, 5)
    assert out.shape == (2, 3, 3)
    np.testing.assert_array_equal(out, L[..., [0, 1, 5]])
    rp = radial_points(random_scenes(np.random.default_rng(5), (4,)))
    Lc = planar(L_cij(rp.x_n, rp.d, rp.z_n))
    assert Lc.shape == (6, 3) and np.all(Lc[:, 2] == 0.0)
