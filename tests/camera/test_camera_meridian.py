"""The meridian-plane root-find: the reflection point, to machine precision, whatever the batch."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from test_catadioptric import CAMERAS, scene_points

from radial_ibvs_gym.camera import meridian
from radial_ibvs_gym.camera.meridian import MeridianSolver


def _meridian_coordinates(camera, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    return np.hypot(points[:, 0], points[:, 1]), points[:, 2] + camera.camera_z


def _bisected(solver: MeridianSolver, rho: np.ndarray, z: np.ndarray, s: np.ndarray) -> np.ndarray:
    """An independent reference: 60 bisections of the residual in a bracket of +-1 um about ``s``.

    The bracket is narrow so it holds this root only (a cone's apex, the invalid branch).
    """
    width = 1e-6
    lo, hi = s - width, s + width
    g_lo, _ = solver.residual(lo, rho, z)
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        g_mid, _ = solver.residual(mid, rho, z)
        left = np.sign(g_mid) == np.sign(g_lo)
        lo, g_lo = np.where(left, mid, lo), np.where(left, g_mid, g_lo)
        hi = np.where(left, hi, mid)
    return 0.5 * (lo + hi)


@pytest.mark.parametrize("name", list(CAMERAS))
def test_the_root_is_the_bisected_one_to_a_few_ulps(name: str) -> None:
    camera = CAMERAS[name]
    solver = camera._solver
    points = scene_points(camera, np.random.default_rng(7), 2000)
    rho, z = _meridian_coordinates(camera, points)
    s = solver.solve(rho, z)
    found = np.isfinite(s)
    assert found.sum() > 500
    reference = _bisected(solver, rho[found], z[found], s[found])
    # a mirror radius of a few centimetres: 1e-15 m is a few units in the last place
    np.testing.assert_allclose(s[found], reference, rtol=0.0, atol=1e-15)
    _, valid = solver.residual(s[found], rho[found], z[found])
    assert valid.all()


@pytest.mark.parametrize("name", ["hyperboloid-central", "hyperboloid-noncentral+8mm", "sphere"])
@settings(max_examples=20, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), size=st.integers(1, 60))
def test_a_point_gets_the_same_bits_alone_and_in_any_batch(name: str, seed: int, size: int) -> None:
    camera = CAMERAS[name]
    points = scene_points(camera, np.random.default_rng(seed), size)
    rho, z = _meridian_coordinates(camera, points)
    together = camera._solver.solve(rho, z)
    alone = np.array([camera._solver.solve(rho[i : i + 1], z[i : i + 1])[0] for i in range(size)])
    np.testing.assert_array_equal(together, alone)


def test_more_iterations_do_not_move_the_root(monkeypatch: pytest.MonkeyPatch) -> None:
    camera = CAMERAS["hyperboloid-noncentral+8mm"]
    points = scene_points(camera, np.random.default_rng(3), 3000)
    rho, z = _meridian_coordinates(camera, points)
    shipped = camera._solver.solve(rho, z)
    monkeypatch.setattr(meridian, "ITERATIONS", 3 * meridian.ITERATIONS)
    longer = camera._solver.solve(rho, z)
    np.testing.assert_array_equal(np.isfinite(shipped), np.isfinite(longer))
    found = np.isfinite(shipped)
    np.testing.assert_allclose(shipped[found], longer[found], rtol=0.0, atol=1e-15)


def test_points_without_a_reflection_get_nan() -> None:
    camera = CAMERAS["hyperboloid-central"]
    # straight above the mirror, far out: no ray from the pinhole reaches them via the mirror
    rho = np.array([0.001, 0.002])
    z = np.array([5.0, 8.0])
    assert np.isnan(camera._solver.solve(rho, z)).all()


def _points_anywhere(rng: np.random.Generator, size: int) -> tuple[np.ndarray, np.ndarray]:
    """Meridian coordinates in every direction, 1 cm to 50 m from the mirror frame's origin."""
    angle = rng.uniform(-0.5 * np.pi, 0.5 * np.pi, size)
    distance = np.exp(rng.uniform(np.log(0.01), np.log(50.0), size))
    return np.maximum(distance * np.cos(angle), 1e-6), distance * np.sin(angle)


@pytest.mark.parametrize("name", list(CAMERAS))
@settings(max_examples=10, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_the_table_bracket_finds_the_grid_search_root(name: str, seed: int) -> None:
    """The fast path (table, bracket, Illinois) gives the reference grid search's root."""
    camera = CAMERAS[name]
    rng = np.random.default_rng(seed)
    points = scene_points(camera, rng, 1500)
    rho, z = _meridian_coordinates(camera, points)
    near_rho, near_z = _points_anywhere(rng, 1500)
    rho, z = np.concatenate([rho, near_rho]), np.concatenate([z, near_z])
    fast = camera._solver.solve(rho, z)
    reference = camera._solver.grid_solve(rho, z)
    np.testing.assert_array_equal(np.isnan(fast), np.isnan(reference))
    found = np.isfinite(fast)
    assert found.sum() > 500
    np.testing.assert_allclose(fast[found], reference[found], rtol=0.0, atol=1e-15)


@pytest.mark.parametrize("name", list(CAMERAS))
def test_the_table_sends_most_points_with_a_root_through_its_bracket(name: str) -> None:
    """The table serves the common case: few points with a root fall back to the grid."""
    camera = CAMERAS[name]
    camera._solver.solve(np.array([1.0]), np.array([0.0]))  # builds the table
    points = scene_points(camera, np.random.default_rng(11), 4000)
    rho, z = _meridian_coordinates(camera, points)
    _, half = camera._solver._table.lookup(rho, z)
    has_root = np.isfinite(camera._solver.grid_solve(rho, z))
    bracketed = np.isfinite(half) & has_root
    assert bracketed.sum() >= 0.95 * has_root.sum()


@pytest.mark.parametrize("name", list(CAMERAS))
def test_cells_marked_rootless_hold_no_root(name: str) -> None:
    """A point whose cell the table marks as rootless has none by the grid search either."""
    camera = CAMERAS[name]
    camera._solver.solve(np.array([1.0]), np.array([0.0]))
    rho, z = _points_anywhere(np.random.default_rng(12), 40000)
    _, half = camera._solver._table.lookup(rho, z)
    rootless = half == np.inf
    assert rootless.sum() > 1000
    assert np.isnan(camera._solver.grid_solve(rho[rootless], z[rootless])).all()
    # and the solver returns NaN for them
    assert np.isnan(camera._solver.solve(rho[rootless], z[rootless])).all()
