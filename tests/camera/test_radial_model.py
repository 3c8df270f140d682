"""Unit tests of eq. (7) and eq. (9) on their own (the mirror-level invariance is in
test_camera_*)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from radial_ibvs_gym.camera.radial import normalise_pixels, radial_points

angles = st.floats(-np.pi, np.pi, allow_nan=False)


@given(
    phi=angles,
    r=st.floats(1e-3, 2.0),
    fx=st.floats(200, 3000),
    ratio=st.floats(0.5, 2.0),
    mu=st.tuples(st.floats(0, 2000), st.floats(0, 2000)),
)
def test_eq7_recovers_the_direction_of_the_metric_point(phi, r, fx, ratio, mu):
    # x_m anywhere on the radial line at angle phi: eq. (7) must give (cos phi, sin phi)
    fy = fx / ratio
    x_m = r * np.array([np.cos(phi), np.sin(phi)])
    pixel = np.array([fx * x_m[0] + mu[0], fy * x_m[1] + mu[1]])
    x_n = normalise_pixels(pixel, mu, rho_f=fx / fy)
    np.testing.assert_allclose(x_n, [np.cos(phi), np.sin(phi)], atol=1e-9)


def test_eq7_needs_the_focal_ratio() -> None:
    pixel = np.array([600.0 + 100.0, 500.0 + 100.0])
    right = normalise_pixels(pixel, (600.0, 500.0), rho_f=2.0)
    wrong = normalise_pixels(pixel, (600.0, 500.0), rho_f=1.0)
    np.testing.assert_allclose(right, np.array([1.0, 2.0]) / np.sqrt(5.0))
    assert np.linalg.norm(right - wrong) > 0.1


def test_eq7_is_batched() -> None:
    rng = np.random.default_rng(1)
    pixels = rng.uniform(0, 1000, (4, 7, 2))
    out = normalise_pixels(pixels, (500.0, 400.0), 1.1)
    assert out.shape == (4, 7, 2)
    np.testing.assert_allclose(np.linalg.norm(out, axis=-1), 1.0)
    np.testing.assert_array_equal(out[2, 3], normalise_pixels(pixels[2, 3], (500.0, 400.0), 1.1))


@given(x=st.floats(-50, 50), y=st.floats(-50, 50), z=st.floats(-50, 50), s=st.floats(1e-3, 1e3))
def test_eq9_is_scale_invariant_and_unit(x, y, z, s):
    if np.hypot(x, y) < 1e-6:
        return
    rp = radial_points([[x, y, z]])
    np.testing.assert_allclose(np.linalg.norm(rp.x_n, axis=-1), 1.0)
    np.testing.assert_allclose(radial_points([[s * x, s * y, s * z]]).x_n, rp.x_n, atol=1e-12)
    np.testing.assert_allclose(rp.d * rp.z_n, [z], atol=1e-9)


def test_eq9_sign_flips_for_concave_mirrors() -> None:
    p = [[1.0, 2.0, 0.5]]
    np.testing.assert_allclose(radial_points(p, sign=-1).x_n, -radial_points(p).x_n)


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda: radial_points([[0.0, 0.0, 1.0]]), "optical axis"),
        (lambda: radial_points([[np.nan, 0.0, 1.0]]), "finite"),
        (lambda: radial_points([[1.0, 0.0]]), r"shape \(\.\.\., 3\)"),
        (lambda: radial_points([[1.0, 0.0, 0.0]], sign=0), "sign"),
        (lambda: normalise_pixels([[10.0, 20.0]], (10.0, 20.0)), "principal point"),
        (lambda: normalise_pixels([[10.0, 20.0]], (0.0, 0.0), rho_f=0.0), "rho_f"),
        (lambda: normalise_pixels([[np.inf, 20.0]], (0.0, 0.0)), "finite"),
        (lambda: normalise_pixels([["a", 20.0]], (0.0, 0.0)), "numeric"),
    ],
)
def test_bad_input_is_named(call, match) -> None:
    with pytest.raises(ValueError, match=match):
        call()
