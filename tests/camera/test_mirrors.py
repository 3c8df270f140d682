from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from radial_ibvs_gym.camera import (
    MIRROR_A,
    MIRROR_B,
    Cone,
    Ellipsoid,
    Hyperboloid,
    Paraboloid,
    Sphere,
)

MIRRORS = {
    "hyperboloid": MIRROR_A,
    "ellipsoid": Ellipsoid(a=0.02, b=0.03, rim_radius=0.015),
    "paraboloid": Paraboloid(focal_length=0.01, rim_radius=0.025),
    "sphere": Sphere(radius=0.03, rim_radius=0.02),
    "cone": Cone(half_angle=0.6, rim_radius=0.025),
}


def test_paper_mirrors_focal_half_distance() -> None:
    # e = sqrt(a^2 + b^2): 34.0000 mm and 36.0000 mm (the round numbers confirm the reading of
    # the paper's table: a radial, b axial)
    assert MIRROR_A.e * 1e3 == pytest.approx(34.0, abs=1e-4)
    assert MIRROR_B.e * 1e3 == pytest.approx(36.0, abs=1e-4)
    assert MIRROR_A.central_camera_z == pytest.approx(-0.034, abs=1e-7)


@pytest.mark.parametrize("name", list(MIRRORS))
@settings(max_examples=50, deadline=None)
@given(frac=st.floats(0.0, 1.0))
def test_profile_lies_on_the_quadric_with_the_right_slope_and_normal(name: str, frac: float):
    m = MIRRORS[name]
    rho = frac * m.rim_radius
    z = float(m.profile_z(rho))
    assert abs(float(m.implicit(rho, z))) <= 1e-15
    h = 1e-7
    lo, hi = max(rho - h, 0.0), min(rho + h, m.rim_radius)
    fd = (float(m.profile_z(hi)) - float(m.profile_z(lo))) / (hi - lo)
    assert float(m.profile_slope(rho)) == pytest.approx(fd, rel=1e-5, abs=1e-5)
    n = m.normal(rho)
    assert np.linalg.norm(n) == pytest.approx(1.0)
    assert abs(n[0] * 1.0 + n[1] * float(m.profile_slope(rho))) <= 1e-12  # normal to tangent
    assert n[1] < 0  # reflective side faces the camera below


@pytest.mark.parametrize("name", list(MIRRORS))
@settings(max_examples=30, deadline=None)
@given(fracs=st.lists(st.floats(0.0, 1.0), min_size=1, max_size=20))
def test_profile_gives_the_height_and_slope_bit_for_bit(name: str, fracs: list[float]) -> None:
    m = MIRRORS[name]
    rho = np.array(fracs) * m.rim_radius
    z, slope = m.profile(rho)
    np.testing.assert_array_equal(z, m.profile_z(rho))
    np.testing.assert_array_equal(slope, m.profile_slope(rho))


@pytest.mark.parametrize("name", list(MIRRORS))
def test_intersect_ray_hits_the_silvered_sheet_first(name: str) -> None:
    m = MIRRORS[name]
    rng = np.random.default_rng(3)
    rho = rng.uniform(0, m.rim_radius, 50)
    phi = rng.uniform(-np.pi, np.pi, 50)
    target = np.stack([rho * np.cos(phi), rho * np.sin(phi), m.profile_z(rho)], -1)
    origin = np.array([0.0, 0.0, m.vertex_z - 0.05 if not m.concave else m.rim_z - 0.01])
    pts, t, hit = m.intersect_ray(np.broadcast_to(origin, target.shape), target - origin)
    assert hit.all()
    np.testing.assert_allclose(pts, target, atol=1e-12)
    np.testing.assert_allclose(t, 1.0, atol=1e-9)
    miss = m.intersect_ray(origin, [1.0, 0.0, 0.0])
    assert not miss[2]


@pytest.mark.parametrize(
    ("make", "match"),
    [
        (lambda: Hyperboloid(a=0.0, b=1.0, rim_radius=0.1), "a must be finite and positive"),
        (lambda: Hyperboloid(a=1.0, b=-1.0, rim_radius=0.1), "b must be"),
        (lambda: Hyperboloid(a=1.0, b=1.0, rim_radius=math.nan), "rim_radius"),
        (lambda: Ellipsoid(a=0.03, b=0.02, rim_radius=0.01), "b > a"),
        (lambda: Ellipsoid(a=0.02, b=0.03, rim_radius=0.02), "smaller than a"),
        (lambda: Sphere(radius=0.02, rim_radius=0.03), "smaller than the sphere radius"),
        (lambda: Cone(half_angle=2.0, rim_radius=0.03), r"half_angle must be in \(0, pi/2\)"),
        (lambda: Paraboloid(focal_length=-1, rim_radius=0.03), "focal_length"),
    ],
)
def test_mirrors_that_are_no_mirror_are_rejected(make, match) -> None:
    with pytest.raises(ValueError, match=match):
        make()
