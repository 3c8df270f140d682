"""The helpers of the teaching notebooks on the camera (``notebooks/_helpers/teaching.py`` and
``teaching_interaction.py``)."""

from __future__ import annotations

import numpy as np
import pytest
from _helpers import teaching
from _helpers import teaching_interaction as ti
from matplotlib.figure import Figure

from radial_ibvs_gym.camera import MIRROR_A, Imperfections, paper_camera, radial_points
from radial_ibvs_gym.features import (
    L_alpha,
    L_alpha_m,
    L_cij,
    L_xn,
    alpha,
    alpha_m,
    c_ij,
    virtual_point_weights,
)


def scene(seed: int = 0, n: int = 6) -> np.ndarray:
    return teaching.sample_scene_points(np.random.default_rng(seed), n, (1.0, 10.0), (-1.5, 1.0))


# --- sampling and measuring -------------------------------------------------------------------


def test_sample_scene_points_are_seeded_and_in_range() -> None:
    a = teaching.sample_scene_points(np.random.default_rng(3), 500, (0.5, 8.0), (-1.8, 1.0))
    b = teaching.sample_scene_points(np.random.default_rng(3), 500, (0.5, 8.0), (-1.8, 1.0))
    np.testing.assert_array_equal(a, b)
    assert a.shape == (500, 3)
    d = np.hypot(a[:, 0], a[:, 1])
    assert d.min() >= 0.5 and d.max() <= 8.0
    assert a[:, 2].min() >= -1.8 and a[:, 2].max() <= 1.0
    azimuth = np.arctan2(a[:, 1], a[:, 0])
    assert azimuth.min() < -2.5 and azimuth.max() > 2.5  # all around the camera


@pytest.mark.parametrize(
    "kwargs",
    [{"n": 0}, {"n": 3, "distance": (0.0, 1.0)}, {"n": 3, "distance": (2.0, 1.0)}],
)
def test_sample_scene_points_rejects_bad_ranges(kwargs: dict) -> None:
    with pytest.raises(ValueError):
        teaching.sample_scene_points(np.random.default_rng(0), **kwargs)
    with pytest.raises(ValueError, match="height"):
        teaching.sample_scene_points(np.random.default_rng(0), 3, height=(1.0, 0.0))


def test_invariance_errors_vanish_for_an_aligned_non_central_camera() -> None:
    camera = paper_camera("A", non_central_offset=0.01)
    points = teaching.sample_scene_points(np.random.default_rng(1), 400)
    errors, visible = teaching.invariance_errors(camera, points)
    assert visible.shape == (400,) and visible.sum() == len(errors) > 300
    np.testing.assert_array_equal(visible, camera.forward(points).visible)
    assert errors.max() < 1e-12
    wrong_ratio, _ = teaching.invariance_errors(camera, points, rho_f=1.1)
    assert wrong_ratio.max() > 1e-2  # eq. (7) needs the right focal ratio


def test_invariance_errors_grow_with_the_tilt() -> None:
    points = teaching.sample_scene_points(np.random.default_rng(2), 300)
    medians = [
        np.median(
            teaching.invariance_errors(
                paper_camera("A", 0.01, Imperfections(tilt=(np.radians(t), 0.0))), points
            )[0]
        )
        for t in (0.01, 0.1, 1.0)
    ]
    assert 1e-5 < medians[0] < medians[1] < medians[2]
    np.testing.assert_allclose(medians[2] / medians[1], 10.0, rtol=0.1)  # linear in the tilt


def test_invariance_errors_with_nothing_visible_are_empty() -> None:
    camera = paper_camera("A", non_central_offset=0.01)
    errors, visible = teaching.invariance_errors(camera, [[1.0, 0.0, 50.0]])  # straight up
    assert errors.shape == (0,) and not visible.any()


def test_axis_crossings_of_simple_rays() -> None:
    z, miss = teaching.axis_crossings(
        [[1.0, 0.0, 0.0], [0.0, 2.0, 1.0], [1.0, 0.0, 0.0]],
        [[-1.0, 0.0, 1.0], [0.0, 1.0, -1.0], [0.0, 1.0, 0.0]],
    )
    np.testing.assert_allclose(z, [1.0, 3.0, 0.0], atol=1e-15)
    np.testing.assert_allclose(miss, [0.0, 0.0, 1.0], atol=1e-15)
    with pytest.raises(ValueError, match="vertical"):
        teaching.axis_crossings([[1.0, 0.0, 0.0]], [[0.0, 0.0, 1.0]])
    with pytest.raises(ValueError, match="shape"):
        teaching.axis_crossings([[1.0, 0.0]], [[0.0, 1.0]])


def test_meridian_fan_meets_the_inner_focus_only_when_central() -> None:
    central = paper_camera("A")
    origins, directions = teaching.meridian_fan(central, 11)
    assert origins.shape == directions.shape == (11, 3)
    np.testing.assert_allclose(np.linalg.norm(directions, axis=-1), 1.0)
    np.testing.assert_allclose(origins[:, 1], 0.0, atol=1e-15)  # the meridian plane y = 0
    assert np.all(origins[:, 0] > 0.0)
    z, miss = teaching.axis_crossings(origins, directions)
    np.testing.assert_allclose(z, MIRROR_A.e - central.camera_z, atol=1e-9)  # inner focus
    assert miss.max() < 1e-12
    z_nc, _ = teaching.axis_crossings(*teaching.meridian_fan(paper_camera("A", 0.01), 11))
    assert np.ptp(z_nc) > 5e-4  # a caustic of about a millimetre
    with pytest.raises(ValueError, match="n_rays"):
        teaching.meridian_fan(central, 1)


def test_mirror_circle_pixels_is_a_circle_about_the_principal_point() -> None:
    camera = paper_camera("B", non_central_offset=0.01)
    ring = teaching.mirror_circle_pixels(camera, 0.02, n=37)
    k = camera.intrinsics
    radius = np.linalg.norm(ring - k.principal_point, axis=-1)
    expected = k.fx * 0.02 / (float(camera.mirror.profile_z(0.02)) - camera.camera_z)
    np.testing.assert_allclose(radius, expected)
    np.testing.assert_allclose(ring[0], ring[-1])


# --- finite differences -------------------------------------------------------------------------


def test_finite_differences_match_the_analytic_matrices() -> None:
    points = scene(4, 7)
    rp = radial_points(points)
    a = virtual_point_weights(radial_points(scene(5, 7)).x_n)
    pairs = [
        (
            L_xn(rp.x_n, rp.d, rp.z_n),
            ti.finite_difference_interaction(lambda r: r.x_n, points),
        ),
        (
            L_cij(rp.x_n, rp.d, rp.z_n),
            ti.finite_difference_interaction(lambda r: c_ij(r.x_n), points),
        ),
        (
            L_alpha(rp.x_n, rp.d, rp.z_n),
            ti.finite_difference_interaction(lambda r: alpha(r.x_n), points, angle=True),
        ),
        (
            L_alpha_m(rp.x_n, rp.d, rp.z_n, a),
            ti.finite_difference_interaction(lambda r: alpha_m(r.x_n, a), points, angle=True),
        ),
    ]
    for analytic, numeric in pairs:
        assert analytic.shape == numeric.shape
        assert ti.interaction_error(analytic, numeric) < 1e-6


def test_finite_differences_are_batched_and_support_both_stencils_and_signs() -> None:
    points = np.stack([scene(s) for s in range(3)])  # (3, 6, 3)
    batched = ti.finite_difference_interaction(lambda r: r.x_n, points, sign=-1)
    assert batched.shape == (3, 6, 2, 6)
    single = ti.finite_difference_interaction(lambda r: r.x_n, points[1], sign=-1)
    np.testing.assert_allclose(batched[1], single, rtol=0, atol=1e-12)
    rp = radial_points(points, sign=-1)
    analytic = L_xn(rp.x_n, rp.d, rp.z_n, sign=-1)
    assert ti.interaction_error(analytic, batched) < 1e-6
    three = ti.finite_difference_interaction(lambda r: r.x_n, points, sign=-1, stencil=3)
    assert ti.interaction_error(analytic, three) < 1e-4
    # a coarse step shows the truncation error of the 3-point stencil, not of the 5-point one
    coarse3 = ti.finite_difference_interaction(lambda r: r.x_n, points, step=1e-2, stencil=3)
    coarse5 = ti.finite_difference_interaction(lambda r: r.x_n, points, step=1e-2)
    plus = radial_points(points)
    exact = L_xn(plus.x_n, plus.d, plus.z_n)
    assert np.abs(coarse5 - exact).max() < 0.1 * np.abs(coarse3 - exact).max()


@pytest.mark.parametrize(
    ("kwargs", "match"), [({"step": 0.0}, "step"), ({"stencil": 4}, "stencil")]
)
def test_finite_differences_reject_bad_settings(kwargs: dict, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        ti.finite_difference_interaction(lambda r: r.x_n, scene(), **kwargs)


def test_interaction_error_is_relative_with_a_floor() -> None:
    assert ti.interaction_error([1.0, 0.0], [1.0, 0.0]) == 0.0
    assert ti.interaction_error([2.2, 0.0], [2.0, 0.0]) == pytest.approx(0.1)
    assert ti.interaction_error([0.0, 1e-6], [0.0, 0.0]) == pytest.approx(1e-3)
    with pytest.raises(ValueError, match="shapes differ"):
        ti.interaction_error(np.zeros(6), np.zeros((1, 6)))


def test_column_table_lays_out_named_rows() -> None:
    table = ti.column_table({"analytic": np.arange(6.0), "fd": -np.arange(6.0)})
    lines = table.splitlines()
    assert len(lines) == 3
    assert lines[0].split() == list(ti.TWIST_COLUMNS)
    assert lines[1].split()[0] == "analytic" and lines[2].split()[-1] == "-5.000000"
    assert len({len(line) for line in lines}) == 1  # aligned
    with pytest.raises(ValueError, match="columns"):
        ti.column_table({"short": [1.0, 2.0]})


# --- drawing ----------------------------------------------------------------------------------


def test_plot_mirror_rays_draws_the_visible_points() -> None:
    camera = paper_camera("A", non_central_offset=0.01)
    points = np.array([[3.0, 1.0, -1.0], [2.0, -2.0, 0.3], [0.5, 0.0, 40.0]])  # last: not seen
    ax = Figure().add_subplot()
    drawn = teaching.plot_mirror_rays(ax, camera, points, label="mirror A")
    assert drawn == int(camera.forward(points).visible.sum()) == 2
    assert len(ax.lines) == 1 + 2 * drawn + 1  # profile, two segments per point, pinhole


def test_plot_ray_fan_returns_the_axis_crossings() -> None:
    ax = Figure().add_subplot()
    z, miss = teaching.plot_ray_fan(ax, paper_camera("A"), n_rays=5)
    assert z.shape == miss.shape == (5,)
    np.testing.assert_allclose(z, 2.0 * MIRROR_A.e, atol=1e-9)
    assert len(ax.lines) == 1 + 3 * 5 + 1


def test_plot_image_frame_sets_image_axes() -> None:
    camera = paper_camera("B")
    ax = Figure().add_subplot()
    teaching.plot_image_frame(ax, camera)
    k = camera.intrinsics
    assert ax.get_xlim() == (0.0, float(k.width))
    assert ax.get_ylim() == (float(k.height), 0.0)  # v down
    assert len(ax.patches) == 3
