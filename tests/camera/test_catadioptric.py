"""Exact catadioptric projection: law of reflection, radial invariance, round trips, visibility."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from radial_ibvs_gym.camera import (
    CatadioptricCamera,
    Cone,
    Ellipsoid,
    Imperfections,
    Intrinsics,
    Paraboloid,
    Sphere,
    normalise_pixels,
    paper_camera,
    presets,
    radial_points,
)
from radial_ibvs_gym.camera.presets import ELEVATION_RANGE_DEG, MIRROR_A

# fx != fy on purpose: eq. (7) must use rho_f
K = Intrinsics(fx=1100.0, fy=1000.0, mu_x=640.5, mu_y=511.0, width=1280, height=1024)
# rim above the upper focus (z = 22.4 mm), so reflected rays leave through the opening
ELLIPSOID = Ellipsoid(a=0.02, b=0.03, rim_radius=0.012)

CAMERAS = {
    "hyperboloid-central": CatadioptricCamera(MIRROR_A, K),
    "hyperboloid-noncentral+8mm": CatadioptricCamera(MIRROR_A, K, camera_z=-0.026),
    "hyperboloid-noncentral-5mm": CatadioptricCamera(MIRROR_A, K, camera_z=-0.039),
    "ellipsoid-central": CatadioptricCamera(ELLIPSOID, K, lens_radius=0.004),
    "ellipsoid-noncentral": CatadioptricCamera(ELLIPSOID, K, camera_z=-0.018, lens_radius=0.004),
    "paraboloid": CatadioptricCamera(
        Paraboloid(focal_length=0.01, rim_radius=0.025), K, camera_z=-0.06
    ),
    "sphere": CatadioptricCamera(Sphere(radius=0.03, rim_radius=0.02), K, camera_z=-0.08),
    "cone": CatadioptricCamera(Cone(half_angle=0.6, rim_radius=0.025), K, camera_z=-0.05),
}


def scene_points(camera: CatadioptricCamera, rng: np.random.Generator, n: int) -> np.ndarray:
    """Points all around, 0.5-20 m away, at elevations spanning the camera's field of view."""
    lo, hi = camera.elevation_range()
    r = rng.uniform(0.5, 20.0, n)
    phi = rng.uniform(-np.pi, np.pi, n)
    elev = rng.uniform(lo - 0.1, hi + 0.1, n)
    return np.stack([r * np.cos(phi), r * np.sin(phi), r * np.tan(elev)], axis=-1)


@pytest.mark.parametrize("name", list(CAMERAS))
@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_law_of_reflection_and_radial_invariance(name: str, seed: int) -> None:
    camera = CAMERAS[name]
    points = scene_points(camera, np.random.default_rng(seed), 40)
    proj = camera.forward(points)
    vis = proj.visible
    assert vis.sum() >= 10, "too few visible points: the test would be vacuous"
    angle_error, coplanarity = camera.reflection_angle_error(points[vis], proj.mirror_points[vis])
    assert angle_error.max() <= 1e-9
    assert np.abs(coplanarity).max() <= 1e-9
    # eq. (7) on the exact pixels == eq. (9) on the 3D points: the invariance of the method
    x_n_pixels = normalise_pixels(proj.pixels[vis], K.principal_point, K.rho_f)
    x_n_points = radial_points(points[vis], sign=camera.mirror.radial_sign).x_n
    np.testing.assert_allclose(x_n_pixels, x_n_points, atol=1e-9, rtol=0)


def random_mirror_pixels(camera: CatadioptricCamera, rng: np.random.Generator, n: int):
    """Pixels of random mirror points between the blind radius and the visible rim."""
    r = np.sqrt(rng.uniform(camera.blind_radius**2, camera.visible_radius**2, n)) * 0.999
    phi = rng.uniform(-np.pi, np.pi, n)
    z = camera.mirror.profile_z(r) - camera.camera_z
    x_m = np.stack([r * np.cos(phi), r * np.sin(phi)], -1) / z[:, None]
    return camera.true_intrinsics.project(x_m)


@pytest.mark.parametrize("name", list(CAMERAS))
def test_round_trip_pixel_ray_point_pixel(name: str) -> None:
    camera = CAMERAS[name]
    rng = np.random.default_rng(7)
    pixels = random_mirror_pixels(camera, rng, 300)
    origins, directions = camera.backward(pixels)
    assert np.isfinite(directions).all()
    np.testing.assert_allclose(np.linalg.norm(directions, axis=-1), 1.0)
    points = origins + rng.uniform(0.5, 10.0, (300, 1)) * directions
    proj = camera.forward(points)
    assert proj.visible.all()
    assert np.abs(proj.pixels - pixels).max() <= 1e-6


def distance_to_point(origins, directions, point) -> np.ndarray:
    v = point - origins
    return np.linalg.norm(v - np.sum(v * directions, -1, keepdims=True) * directions, axis=-1)


def test_central_rays_meet_at_the_inner_focus_and_non_central_do_not() -> None:
    rng = np.random.default_rng(1)
    central = CAMERAS["hyperboloid-central"]
    inner_focus = np.array([0.0, 0.0, MIRROR_A.e - central.camera_z])  # camera frame
    o, d = central.backward(random_mirror_pixels(central, rng, 200))
    assert distance_to_point(o, d, inner_focus).max() <= 1e-9
    non_central = CAMERAS["hyperboloid-noncentral+8mm"]
    o, d = non_central.backward(random_mirror_pixels(non_central, rng, 200))
    focus = np.array([0.0, 0.0, MIRROR_A.e - non_central.camera_z])
    assert distance_to_point(o, d, focus).max() > 1e-4  # they miss it by up to ~0.9 mm
    assert central.is_central and not non_central.is_central


def invariance_errors(camera: CatadioptricCamera, seed: int = 0) -> np.ndarray:
    """|x_n(eq. 7 with the nominal calibration) - x_n(eq. 9)| over 2000 random scene points."""
    points = scene_points(camera, np.random.default_rng(seed), 2000)
    proj = camera.forward(points)
    vis = proj.visible
    x_n = normalise_pixels(proj.pixels[vis], K.principal_point, K.rho_f)
    return np.linalg.norm(x_n - radial_points(points[vis]).x_n, axis=-1)


@pytest.mark.parametrize(
    ("imperfections", "low", "high"),
    [
        # Measured with seed 0 (mirror A, pinhole 4 mm above the focus), median / max error on
        # the unit circle (~radians): 3 px principal-point offset 1.4e-2 / 1.1e-1; 2 % focal
        # ratio 7.0e-3 / 9.9e-3; 1 deg tilt 7.1e-2 / 6.2e-1 (0.1 deg: 7.2e-3 / 6.0e-2);
        # 1 mm axis offset 5.7e-2 / 5.6e-1 (0.1 mm: 5.7e-3 / 5.3e-2). The worst points are those
        # imaged near the principal point (steep elevations), where a pixel is a large angle.
        (Imperfections(principal_point_offset=(3.0, -2.0)), 5e-3, 3e-2),
        (Imperfections(focal_ratio_error=0.02), 3e-3, 1.5e-2),
        (Imperfections(tilt=(np.radians(1.0), 0.0)), 3e-2, 1.5e-1),
        (Imperfections(axis_offset=(1e-3, 0.0)), 3e-2, 1.5e-1),
    ],
)
def test_imperfections_break_the_radial_invariance_by_a_bounded_amount(
    imperfections: Imperfections, low: float, high: float
) -> None:
    perfect = CatadioptricCamera(MIRROR_A, K, camera_z=-0.03)
    assert invariance_errors(perfect).max() <= 1e-9
    camera = CatadioptricCamera(MIRROR_A, K, camera_z=-0.03, imperfections=imperfections)
    assert low <= np.median(invariance_errors(camera)) <= high


def test_off_axis_camera_still_obeys_the_law_of_reflection() -> None:
    camera = CatadioptricCamera(
        MIRROR_A, K, imperfections=Imperfections(axis_offset=(1e-3, -5e-4), tilt=(0.01, 0.02))
    )
    points = scene_points(camera, np.random.default_rng(2), 200)
    proj = camera.forward(points)
    vis = proj.visible
    assert vis.sum() > 100
    angle_error, coplanarity = camera.reflection_angle_error(points[vis], proj.mirror_points[vis])
    assert angle_error.max() <= 1e-9 and np.abs(coplanarity).max() <= 1e-9
    pixels = proj.pixels[vis]
    o, d = camera.backward(pixels)
    back = camera.forward(o + 3.0 * d)
    assert np.abs(back.pixels - pixels).max() <= 1e-6


def test_pixel_noise_is_seeded_and_has_the_requested_std() -> None:
    camera = CatadioptricCamera(MIRROR_A, K, imperfections=Imperfections(pixel_noise_std=0.5))
    points = scene_points(camera, np.random.default_rng(0), 4000)
    clean = camera.forward(points)
    a = camera.forward(points, rng=np.random.default_rng(42))
    b = camera.forward(points, rng=np.random.default_rng(42))
    np.testing.assert_array_equal(a.pixels, b.pixels)
    noise = (a.pixels - clean.pixels)[clean.visible]
    assert noise.std() == pytest.approx(0.5, rel=0.05)
    assert abs(noise.mean()) < 0.05


@pytest.mark.parametrize("name", [n for n in CAMERAS if not n.startswith("ellipsoid")])
def test_fast_visibility_agrees_with_the_root_find(name: str) -> None:
    camera = CAMERAS[name]
    points = scene_points(camera, np.random.default_rng(5), 3000)
    exact = camera.forward(points).visible
    assert 0.2 < exact.mean() < 1.0  # both visible and hidden points are tested
    assert (camera.visible(points) == exact).all()


@pytest.mark.parametrize("name", [n for n in CAMERAS if not n.startswith("ellipsoid")])
@settings(max_examples=20, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_visible_radius_bounds_agree_with_visible(name: str, seed: int) -> None:
    camera = CAMERAS[name]
    points = scene_points(camera, np.random.default_rng(seed), 400)
    bounds = camera.visible_radius_bounds(points[:, 2])
    assert bounds is not None
    rho = np.hypot(points[:, 0], points[:, 1])
    fast = (rho > bounds[0]) & (rho < bounds[1])
    exact = camera.visible(points)
    # equal except within a nanometre of a limiting ray, where rounding may decide either way
    edge = (np.abs(rho - bounds[0]) < 1e-9) | (np.abs(rho - bounds[1]) < 1e-9)
    np.testing.assert_array_equal(fast[~edge], exact[~edge])


def test_visible_radius_bounds_need_an_on_axis_convex_camera() -> None:
    tilted = paper_camera("A", imperfections=Imperfections(tilt=(0.01, 0.0)))
    assert tilted.visible_radius_bounds([0.5]) is None
    assert CAMERAS["ellipsoid-central"].visible_radius_bounds([0.5]) is None


def test_points_above_the_rim_ray_and_in_the_blind_cone_are_hidden() -> None:
    camera = paper_camera("A")
    lo, hi = camera.elevation_range()
    r = 5.0
    for elev, seen in (
        (hi + 0.02, False),
        (hi - 0.02, True),
        (lo + 0.02, True),
        (lo - 0.02, False),
    ):
        point = np.array([[r, 0.0, r * np.tan(elev) + camera.camera_z]])
        point[0, 2] -= camera.camera_z  # camera frame; elevation measured from the mirror centre
        assert bool(camera.forward(point).visible[0]) is seen, (elev, seen)
        assert bool(camera.visible(point)[0]) is seen


@pytest.mark.parametrize(("mirror", "offset"), list(ELEVATION_RANGE_DEG))
def test_preset_fields_of_view_match_their_documentation(mirror: str, offset: float) -> None:
    lo, hi = np.degrees(paper_camera(mirror, non_central_offset=offset).elevation_range())
    documented = ELEVATION_RANGE_DEG[(mirror, offset)]
    assert (lo, hi) == pytest.approx(documented, abs=0.05)
    assert f"{documented[0]:+.2f} to {documented[1]:+.2f}" in presets.__doc__


def test_batched_forward_equals_loop() -> None:
    camera = CAMERAS["hyperboloid-noncentral+8mm"]
    points = scene_points(camera, np.random.default_rng(9), 24).reshape(4, 6, 3)
    batched = camera.forward(points)
    assert batched.pixels.shape == (4, 6, 2) and batched.visible.shape == (4, 6)
    for i in range(4):
        single = camera.forward(points[i])
        np.testing.assert_array_equal(single.pixels, batched.pixels[i])
        np.testing.assert_array_equal(single.visible, batched.visible[i])


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda: CAMERAS["cone"].forward([[1.0, np.nan, 0.0]]), "finite"),
        (lambda: CAMERAS["cone"].forward([[1.0, 0.0]]), r"shape \(\.\.\., 3\)"),
        (lambda: CAMERAS["cone"].backward([[np.inf, 0.0]]), "finite"),
        (lambda: CatadioptricCamera(MIRROR_A, K, camera_z=0.03), "inside or behind the mirror"),
        (lambda: CatadioptricCamera(ELLIPSOID, K, camera_z=-0.05), "inside the concave"),
        (
            lambda: CatadioptricCamera(Paraboloid(focal_length=0.01, rim_radius=0.02), K),
            "no central pinhole position",
        ),
        (
            lambda: CatadioptricCamera(
                MIRROR_A, Intrinsics(fx=1100, fy=1100, mu_x=4.5, mu_y=4.5, width=10, height=10)
            ),
            "nothing is visible",
        ),
        (lambda: paper_camera("C"), r"unknown mirror 'C'; valid: \['A', 'B'\]"),
        (lambda: Imperfections(pixel_noise_std=-1.0), "pixel_noise_std must be >= 0"),
        (lambda: Imperfections(tilt=(np.nan, 0.0)), "tilt must be two finite numbers"),
        (lambda: Imperfections(focal_ratio_error=-1.0), "focal_ratio_error must be > -1"),
        (
            lambda: Intrinsics(fx=0.0, fy=1.0, mu_x=0, mu_y=0, width=10, height=10),
            "fx must be finite and positive",
        ),
        (
            lambda: Intrinsics(fx=1.0, fy=1.0, mu_x=0, mu_y=0, width=10.5, height=10),
            "width must be a positive integer",
        ),
    ],
)
def test_bad_input_is_named(call, match) -> None:
    with pytest.raises(ValueError, match=match):
        call()


def test_points_without_reflection_are_hidden_not_errors() -> None:
    camera = paper_camera("A")
    proj = camera.forward([[0.0, 0.0, 5.0], [0.001, 0.0, 50.0], [3.0, 1.0, -0.5]])
    assert proj.visible.tolist() == [False, False, True]
    assert np.isnan(proj.pixels[0]).all() and np.isfinite(proj.pixels[2]).all()
