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
