"""The geometry helpers: angle wrapping, rotations, the SE(3) exponential, rigid motions."""

from __future__ import annotations

import math

import hypothesis.extra.numpy as hnp
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.typing import NDArray

from radial_ibvs_gym.geometry import (
    apply_twist_to_points,
    rot2,
    rot_x,
    rot_y,
    rot_z,
    se3_exp,
    skew,
    so3_exp,
    world_to_camera,
)
from radial_ibvs_gym.geometry import wrap_angle as wrap

PI = np.pi
SETTINGS = settings(max_examples=100, deadline=None)
boundary_angles = st.sampled_from(
    [PI, -PI, 3 * PI, -3 * PI, 2 * PI, -2 * PI, 0.0, -0.0, np.nextafter(PI, 0.0)]
)
angles = st.one_of(st.floats(-1e6, 1e6), st.floats(-10.0, 10.0), boundary_angles)
vectors3 = hnp.arrays(np.float64, 3, elements=st.floats(-10.0, 10.0))


def expm_series(m: NDArray[np.float64], terms: int = 60) -> NDArray[np.float64]:
    """Matrix exponential by its Taylor series (reference for small to moderate norms)."""
    out = np.eye(m.shape[-1])
    term = np.eye(m.shape[-1])
    for k in range(1, terms):
        term = term @ m / k
        out = out + term
    return out


# --- wrap_angle --------------------------------------------------------------------------------


@SETTINGS
@given(x=angles)
def test_wrap_angle_range_equivalence_and_idempotence(x: float) -> None:
    w = float(wrap(x))
    assert -PI <= w < PI
    # the same angle: w - x is a multiple of 2 pi (to the rounding of x + pi)
    k = round((w - x) / (2 * PI))
    assert abs(w - x - 2 * PI * k) <= 4 * np.spacing(abs(x) + PI)
    # idempotent, exactly
    assert float(wrap(w)) == w


def test_wrap_angle_at_plus_minus_pi_exactly() -> None:
    assert wrap(PI) == -PI
    assert wrap(-PI) == -PI
    assert wrap(3 * PI) == -PI
    assert wrap(np.nextafter(PI, 0.0)) in (np.nextafter(PI, 0.0), -PI)
    np.testing.assert_array_equal(wrap(np.array([[PI, -PI], [0.0, 2 * PI]])), [[-PI, -PI], [0, 0]])
    assert wrap(np.array([0.5, -0.5])).shape == (2,)


def test_wrap_angle_is_half_open_just_below_minus_pi() -> None:
    """Regression: np.mod(-tiny, 2 pi) rounds to 2 pi, which used to wrap this angle to +pi."""
    x = np.nextafter(-PI, -np.inf)
    assert wrap(x) < PI


# --- rotations ---------------------------------------------------------------------------------


def test_rotations_are_right_handed() -> None:
    ex, ey, ez = np.eye(3)
    np.testing.assert_allclose(rot_z(PI / 2) @ ex, ey, atol=1e-15)
    np.testing.assert_allclose(rot_z(PI / 2) @ ey, -ex, atol=1e-15)
    np.testing.assert_allclose(rot_x(PI / 2) @ ey, ez, atol=1e-15)
    np.testing.assert_allclose(rot_x(PI / 2) @ ez, -ey, atol=1e-15)
    np.testing.assert_allclose(rot_y(PI / 2) @ ez, ex, atol=1e-15)
    np.testing.assert_allclose(rot_y(PI / 2) @ ex, -ez, atol=1e-15)
    np.testing.assert_allclose(rot2(PI / 2) @ [1.0, 0.0], [0.0, 1.0], atol=1e-15)


@SETTINGS
@given(a=st.floats(-10.0, 10.0))
def test_axis_rotations_are_exponentials(a: float) -> None:
    for rot, axis in ((rot_x, 0), (rot_y, 1), (rot_z, 2)):
        w = np.zeros(3)
        w[axis] = a
        np.testing.assert_allclose(rot(a), so3_exp(w), atol=1e-14)
    np.testing.assert_allclose(rot2(a), rot_z(a)[:2, :2], atol=0)


def test_rotations_are_batched() -> None:
    a = np.linspace(-3, 3, 12).reshape(3, 4)
    for rot in (rot_x, rot_y, rot_z):
        out = rot(a)
        assert out.shape == (3, 4, 3, 3)
        np.testing.assert_array_equal(out[1, 2], rot(a[1, 2]))
    assert rot2(a).shape == (3, 4, 2, 2)


@SETTINGS
@given(w=vectors3, p=vectors3)
def test_skew_is_the_cross_product(w: NDArray[np.float64], p: NDArray[np.float64]) -> None:
    np.testing.assert_allclose(skew(w) @ p, np.cross(w, p), atol=1e-12)


# --- so3_exp, se3_exp --------------------------------------------------------------------------


@SETTINGS
@given(w=st.one_of(vectors3, vectors3.map(lambda v: v * 1e-5), vectors3.map(lambda v: v * 1e-9)))
def test_so3_exp_is_a_rotation(w: NDArray[np.float64]) -> None:
    r = so3_exp(w)
    np.testing.assert_allclose(r @ r.T, np.eye(3), atol=1e-13)
    assert np.linalg.det(r) == pytest.approx(1.0, abs=1e-13)
    np.testing.assert_allclose(r @ w, w, atol=1e-12)  # the axis is fixed


@SETTINGS
@given(
    w=vectors3.map(lambda v: v / max(1.0, float(np.linalg.norm(v)))),
    scale=st.sampled_from([1e-12, 1e-8, 1e-5, 9.9e-5, 1.01e-4, 1e-3, 0.1, 1.0]),
)
def test_so3_exp_agrees_with_the_taylor_series(w: NDArray[np.float64], scale: float) -> None:
    v = w * scale
    np.testing.assert_allclose(so3_exp(v), expm_series(skew(v)), rtol=0, atol=2e-15)


@SETTINGS
@given(v=vectors3, w=vectors3.map(lambda v: v / 5.0))
def test_se3_exp_agrees_with_the_taylor_series(
    v: NDArray[np.float64], w: NDArray[np.float64]
) -> None:
    hat = np.zeros((4, 4))
    hat[:3, :3] = skew(w)
    hat[:3, 3] = v
    np.testing.assert_allclose(se3_exp(np.concatenate([v, w])), expm_series(hat), atol=1e-12)


@SETTINGS
@given(v=vectors3)
def test_se3_exp_of_a_pure_translation(v: NDArray[np.float64]) -> None:
    expected = np.eye(4)
    expected[:3, 3] = v
    np.testing.assert_array_equal(se3_exp(np.concatenate([v, np.zeros(3)])), expected)


def test_se3_exp_is_batched() -> None:
    twists = np.random.default_rng(0).normal(size=(2, 5, 6))
    out = se3_exp(twists)
    assert out.shape == (2, 5, 4, 4)
    np.testing.assert_allclose(out[1, 3], se3_exp(twists[1, 3]), atol=0)


# --- apply_twist_to_points ---------------------------------------------------------------------


@SETTINGS
@given(
    points=hnp.arrays(np.float64, (4, 3), elements=st.floats(-10.0, 10.0)),
    twist=hnp.arrays(np.float64, 6, elements=st.floats(-2.0, 2.0)),
)
def test_apply_twist_derivative_is_minus_v_minus_omega_cross_p(
    points: NDArray[np.float64], twist: NDArray[np.float64]
) -> None:
    h = 1e-5
    numeric = (
        apply_twist_to_points(points, twist, h) - apply_twist_to_points(points, twist, -h)
    ) / (2 * h)
    expected = -twist[:3] - np.cross(twist[3:], points)
    np.testing.assert_allclose(numeric, expected, rtol=0, atol=1e-7 * (1 + np.abs(expected).max()))
    np.testing.assert_array_equal(apply_twist_to_points(points, twist, 0.0), points)


def test_apply_twist_moves_points_opposite_to_the_camera() -> None:
    p = np.array([[2.0, 0.0, 0.0]])
    # the camera moves 0.5 m forward: the point is 0.5 m closer
    np.testing.assert_allclose(apply_twist_to_points(p, [0.5, 0, 0, 0, 0, 0], 1.0), [[1.5, 0, 0]])
    # the camera turns +90 deg about z: a point ahead is now on its right (-y)
    out = apply_twist_to_points(p, [0, 0, 0, 0, 0, math.pi / 2], 1.0)
    np.testing.assert_allclose(out, [[0.0, -2.0, 0.0]], atol=1e-15)
    # exact for finite motions: back and forth is the identity
    twist = np.array([0.3, -0.2, 0.1, 0.4, -0.5, 1.2])
    there = apply_twist_to_points(p, twist, 0.7)
    np.testing.assert_allclose(apply_twist_to_points(there, twist, -0.7), p, atol=1e-14)


# --- world_to_camera ---------------------------------------------------------------------------


def test_world_to_camera_axes() -> None:
    pose = np.array([1.0, 2.0, PI / 2])  # robot at (1, 2) facing +y
    points = np.array([[1.0, 5.0, 0.0], [0.0, 2.0, 3.0]])  # ahead; to the left, above
    out = world_to_camera(points, pose, camera_height=1.0)
    np.testing.assert_allclose(out, [[3.0, 0.0, -1.0], [0.0, 1.0, 2.0]], atol=1e-15)


def test_world_to_camera_broadcasts_a_trajectory_of_poses_over_one_point_set() -> None:
    poses = np.array([[1.0, 2.0, PI / 2], [0.0, 0.0, 0.0], [3.0, -1.0, 2.0]])  # (T, 3)
    points = np.array([[1.0, 5.0, 0.0], [0.0, 2.0, 3.0]])  # (N, 3)
    out = world_to_camera(points, poses, camera_height=1.0)
    assert out.shape == (3, 2, 3)
    for k, pose in enumerate(poses):
        np.testing.assert_allclose(out[k], world_to_camera(points, pose, 1.0), atol=1e-15)


@SETTINGS
@given(
    poses=hnp.arrays(np.float64, (4, 3), elements=st.floats(-50.0, 50.0)),
    points=hnp.arrays(np.float64, (4, 5, 3), elements=st.floats(-20.0, 20.0)),
)
def test_world_to_camera_gives_each_pose_of_a_batch_its_own_bits(
    poses: NDArray[np.float64], points: NDArray[np.float64]
) -> None:
    # the native vector env projects a batch; the scalar env one pose: the same bits
    out = world_to_camera(points, poses, 1.7)
    for k in range(len(poses)):
        np.testing.assert_array_equal(out[k], world_to_camera(points[k], poses[k], 1.7))


def test_relative_pose_agrees_with_world_to_camera_and_wraps_the_yaw() -> None:
    from radial_ibvs_gym.geometry import relative_pose, world_to_camera

    rng = np.random.default_rng(3)
    frames = rng.uniform([-5, -5, -np.pi], [5, 5, np.pi], (50, 3))
    poses = rng.uniform([-5, -5, -np.pi], [5, 5, np.pi], (50, 3))
    rel = relative_pose(frames, poses)
    points = np.concatenate([poses[:, :2], np.zeros((50, 1))], axis=-1)
    for k in range(50):
        in_camera = world_to_camera(points[k : k + 1], frames[k], 0.0)[0]
        np.testing.assert_allclose(rel[k, :2], in_camera[:2], atol=1e-12)
    assert np.all((rel[:, 2] >= -np.pi) & (rel[:, 2] < np.pi))
    np.testing.assert_allclose(relative_pose(frames, frames), 0.0, atol=1e-12)


@SETTINGS
@given(
    st.floats(-50, 50), st.floats(-50, 50), st.floats(-10, 10),
    st.floats(-50, 50), st.floats(-50, 50), st.floats(-10, 10),
)  # fmt: skip
def test_pose_in_frame_is_relative_pose_for_one_pair(fx, fy, fyaw, px, py, pyaw) -> None:
    from radial_ibvs_gym.geometry import pose_in_frame, relative_pose

    frame, pose = np.array([fx, fy, fyaw]), np.array([px, py, pyaw])
    got = np.array(pose_in_frame(frame, pose))
    np.testing.assert_allclose(got, relative_pose(frame, pose), rtol=0, atol=1e-12)
    assert -np.pi <= got[2] < np.pi
    # a frame's own pose is its origin
    np.testing.assert_allclose(pose_in_frame(frame, frame), 0.0, atol=1e-12)
