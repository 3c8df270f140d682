"""The law of reflection in a meridian plane: where a point's ray meets the mirror.

The exact forward projection of :class:`~radial_ibvs_gym.camera.catadioptric.CatadioptricCamera`
needs, for each scene point, the mirror point that reflects it into the on-axis pinhole. By
symmetry that point lies in the plane holding the mirror axis and the scene point (the
meridian plane), so the search is one-dimensional: the signed mirror radius ``s`` at which the
world ray reflected from the pinhole's ray passes through the point.

:class:`MeridianSolver` finds it for any number of points at once: the residual on a fixed grid
of the profile brackets the first valid root, and Illinois iterations (regula falsi that halves
the retained end's residual when it is kept twice) refine it to machine precision. Every point
gets the same fixed number of iterations, so a point's result does not depend on the other
points of the call (one robot or a batch of them give the same bits).

The residual is the law of reflection written without a square root or a division: with the
profile slope ``f'``, the unnormalised normal ``n = (f', -1)`` (towards the camera), the vector
``u = c - m`` from the mirror point to the pinhole and ``p - m`` to the scene point,

    ``w = 2 (u . n) n - |n|^2 u``  (the reflection of ``u`` about ``n``, scaled by ``|n|^2``)
    ``G(s) = w x (p - m)``

``G`` vanishes where the reflected ray is parallel to ``p - m``; the root is the reflection
point when the ray leaves towards ``p`` (``w . (p - m) > 0``), the pinhole sees the silvered
side (``u . n > 0``), and so does the point (``(p - m) . n > 0``).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from radial_ibvs_gym.camera.mirrors import QuadricMirror

__all__ = ["MeridianSolver"]

#: Samples of the bracketing grid along the mirror profile.
GRID = 96
#: Illinois iterations after the grid: the bracket starts at 1/95 of the rim, and the residual
#: is smooth, so 4 reach machine precision and 6 leave a margin
#: (``tests/camera/test_camera_meridian.py``).
ITERATIONS = 6


class MeridianSolver:
    """Reflection points of many points, for one mirror and one on-axis pinhole.

    Parameters
    ----------
    mirror
        The mirror.
    camera_z
        Pinhole position on the axis, mirror frame, metres.
    side
        ``+1`` to search the half of the meridian plane holding the point (convex mirrors),
        ``-1`` for the opposite half (concave: the image is on the other side of the axis).
    """

    def __init__(self, mirror: QuadricMirror, camera_z: float, side: float) -> None:
        self.mirror = mirror
        self.camera_z = float(camera_z)
        self.side = float(side)
        self.grid = self.side * np.linspace(0.0, mirror.rim_radius, GRID)
        mz, slope, dot, wx, wz = self._terms(self.grid)
        self._grid_terms = (mz, slope, wx, wz)
        self._grid_dot_ok = dot > 0.0

    def _terms(self, s: NDArray[np.float64]) -> tuple[NDArray, NDArray, NDArray, NDArray, NDArray]:
        """Mirror height, slope, ``u . n`` and the scaled reflected direction at ``s``."""
        mz, slope = self.mirror.profile(np.abs(s))
        slope = np.where(s < 0.0, -slope, slope)
        ux = -s
        uz = self.camera_z - mz
        dot = ux * slope - uz
        nn = 1.0 + slope * slope
        wx = 2.0 * dot * slope - nn * ux
        wz = -2.0 * dot - nn * uz
        return mz, slope, dot, wx, wz

    def residual(
        self, s: NDArray[np.float64], rho_p: NDArray[np.float64], z_p: NDArray[np.float64]
    ) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
        """Residual ``G(s)`` (m^3) and whether ``s`` is on the valid branch.

        Parameters
        ----------
        s
            Signed mirror radii, metres (any shape broadcasting with the points).
        rho_p, z_p
            The points' distance from the axis and height, mirror frame, metres.
        """
        mz, slope, dot, wx, wz = self._terms(s)
        dx = rho_p - s
        dz = z_p - mz
        g = wx * dz - wz * dx
        valid = (wx * dx + wz * dz > 0.0) & (dot > 0.0) & (dx * slope - dz > 0.0)
        return g, valid

    def _g(
        self, s: NDArray[np.float64], rho_p: NDArray[np.float64], z_p: NDArray[np.float64]
    ) -> NDArray[np.float64]:
        mz, _, _, wx, wz = self._terms(s)
        return wx * (z_p - mz) - wz * (rho_p - s)

    def solve(self, rho_p: NDArray[np.float64], z_p: NDArray[np.float64]) -> NDArray[np.float64]:
        """Signed mirror radius ``(K,)`` of the reflection point of each point, NaN if none.

        Parameters
        ----------
        rho_p, z_p
            ``(K,)`` the points' distance from the axis (> 0) and height, mirror frame, metres.
        """
        mz, slope, wx, wz = self._grid_terms
        grid = self.grid
        dx = rho_p[:, None] - grid
        dz = z_p[:, None] - mz
        g = wx * dz - wz * dx
        # the first sign change whose two ends are on the valid branch: the validity is
        # checked at the few sign changes only (in row-major order, so a row's first comes first)
        rows, cols = np.nonzero(g[:, :-1] * g[:, 1:] <= 0.0)
        ends = np.stack([cols, cols + 1])
        ex, ez = dx[rows, ends], dz[rows, ends]
        valid = (wx[ends] * ex + wz[ends] * ez > 0.0) & (ex * slope[ends] - ez > 0.0)
        keep = np.all(valid & self._grid_dot_ok[ends], axis=0)
        rows, cols = rows[keep], cols[keep]
        first_rows, first = np.unique(rows, return_index=True)
        found = np.zeros(len(rho_p), dtype=bool)
        found[first_rows] = True
        k = np.zeros(len(rho_p), dtype=np.intp)
        k[first_rows] = cols[first]
        rows = np.arange(len(k))
        a, b = grid[k], grid[k + 1]
        g_a, g_b = g[rows, k], g[rows, k + 1]
        with np.errstate(invalid="ignore", divide="ignore"):
            for _ in range(ITERATIONS):
                step = g_b * (b - a) / (g_b - g_a)
                s = np.where(np.isfinite(step), b - step, b)
                s = np.clip(s, np.minimum(a, b), np.maximum(a, b))
                g_s = self._g(s, rho_p, z_p)
                crossed = g_s * g_b < 0.0
                a, g_a = np.where(crossed, b, a), np.where(crossed, g_b, 0.5 * g_a)
                b, g_b = s, g_s
        _, ok = self.residual(b, rho_p, z_p)
        return np.where(found & ok, b, np.nan)
