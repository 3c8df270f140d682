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

The grid costs ``GRID`` residuals a point. :meth:`MeridianSolver.solve` first tries a cheaper
bracket: a table of the grid's own roots over the point's direction and inverse distance (built
once per mirror and pinhole, :func:`_first_guess_table`) interpolates a first guess, and a bracket
of the table's measured error about it is refined by the same Illinois iterations. A point whose
cell is not smooth (a corner without a root, or a bracket wider than half the grid's step), that
is nearer than ``TABLE_NEAR``, or whose bracket holds no valid sign change, goes to the grid; a
point whose cell and its neighbours have no root at any node or middle has none (NaN at once:
outside the field of view). Each point takes one path whatever the other points, so the bits
stay batch-independent.
"""

from __future__ import annotations

import functools
from typing import Any

import numpy as np
from numpy.typing import NDArray

from radial_ibvs_gym.camera import meridian_jit
from radial_ibvs_gym.camera.mirrors import Hyperboloid, QuadricMirror

__all__ = ["MeridianSolver"]

#: Samples of the bracketing grid along the mirror profile.
GRID = 96
#: Illinois iterations in a bracket: the grid's is 1/95 of the rim, the table's at most half
#: that and mostly a few micrometres, and the residual is smooth, so 4 reach machine precision
#: from the table's and 5 from the grid's (``tests/camera/test_camera_meridian.py`` checks it
#: against 15).
ITERATIONS = 5
#: Nodes of the first-guess table in the direction ``tan(theta / 2)`` over [-1, 1] (0.16 to
#: 0.32 degree apart).
TABLE_DIRECTIONS = 721
#: Nodes of the table in the inverse distance, over [0, 1 / TABLE_NEAR].
TABLE_INVERSE = 81
#: Points nearer than this to the mirror frame's origin (metres) go to the grid search.
TABLE_NEAR = 0.05
#: The bracket's half-width: this many times the cell's measured error, at least TABLE_FLOOR.
TABLE_MARGIN = 8.0
TABLE_FLOOR = 1e-10


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
        self._table: _Table | None = None

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

        The table's bracket where it holds a valid root, the grid search elsewhere (the module
        docstring); both give the first valid root to a few units in the last place.

        Parameters
        ----------
        rho_p, z_p
            ``(K,)`` the points' distance from the axis (> 0) and height, mirror frame, metres.
        """
        if self._table is None:
            self._table = _first_guess_table(self.mirror, self.camera_z, self.side)
        compiled = meridian_jit.kernel() if isinstance(self.mirror, Hyperboloid) else None
        if compiled is not None:
            return self._solve_compiled(compiled, rho_p, z_p)
        guess, half = self._table.lookup(rho_p, z_p)
        rootless = half == np.inf
        half[rootless] = np.nan
        n = len(rho_p)
        ends = np.concatenate([guess - half, guess + half])  # both ends in one evaluation
        g_ends, valid_ends = self.residual(ends, np.tile(rho_p, 2), np.tile(z_p, 2))
        a, b, g_a, g_b = ends[:n], ends[n:], g_ends[:n], g_ends[n:]
        found = valid_ends[:n] & valid_ends[n:] & (g_a * g_b <= 0.0)
        rest = np.flatnonzero(~(found | rootless))
        if len(rest):  # the grid's brackets for the others, refined in the same pass
            found[rest], a[rest], b[rest], g_a[rest], g_b[rest] = self._grid_brackets(
                rho_p[rest], z_p[rest]
            )
        s = self._illinois(a, b, g_a, g_b, rho_p, z_p)
        _, ok = self.residual(s, rho_p, z_p)
        return np.where(found & ok, s, np.nan)

    def _solve_compiled(
        self, compiled: Any, rho_p: NDArray[np.float64], z_p: NDArray[np.float64]
    ) -> NDArray[np.float64]:
        """:meth:`solve` through the compiled loop (:mod:`.meridian_jit`), the same bits."""
        table, mirror = self._table, self.mirror
        assert table is not None and isinstance(mirror, Hyperboloid)
        rho = np.ascontiguousarray(rho_p, dtype=np.float64)
        z = np.ascontiguousarray(z_p, dtype=np.float64)
        out = np.empty(len(rho))
        to_grid = np.empty(len(rho), dtype=np.bool_)
        compiled(
            rho,
            z,
            mirror.a,
            mirror.b,
            mirror.b / mirror.a**2,
            self.camera_z,
            table.cells,
            table.shape[0],
            table.shape[1],
            table.d_direction,
            table.d_inverse,
            ITERATIONS,
            out,
            to_grid,
        )
        rest = np.flatnonzero(to_grid)
        if len(rest):  # the grid search for the points the table does not bracket
            out[rest] = self.grid_solve(rho[rest], z[rest])
        return out

    def _illinois(
        self,
        a: NDArray[np.float64],
        b: NDArray[np.float64],
        g_a: NDArray[np.float64],
        g_b: NDArray[np.float64],
        rho_p: NDArray[np.float64],
        z_p: NDArray[np.float64],
    ) -> NDArray[np.float64]:
        """Take ``ITERATIONS`` Illinois steps in the brackets ``[a, b]``; return the last one."""
        with np.errstate(invalid="ignore", divide="ignore"):
            for _ in range(ITERATIONS):
                step = g_b * (b - a) / (g_b - g_a)
                s = np.where(np.isfinite(step), b - step, b)
                # np.clip's arithmetic, without its dispatch cost
                s = np.minimum(np.maximum(s, np.minimum(a, b)), np.maximum(a, b))
                g_s = self._g(s, rho_p, z_p)
                crossed = g_s * g_b < 0.0
                a, g_a = np.where(crossed, b, a), np.where(crossed, g_b, 0.5 * g_a)
                b, g_b = s, g_s
        return b

    def grid_solve(
        self, rho_p: NDArray[np.float64], z_p: NDArray[np.float64]
    ) -> NDArray[np.float64]:
        """:meth:`solve` by the grid search alone: the reference, and the table's source.

        Parameters
        ----------
        rho_p, z_p
            ``(K,)`` the points' distance from the axis (> 0) and height, mirror frame, metres.

        Returns
        -------
        numpy.ndarray
            ``(K,)`` signed mirror radii, metres, NaN where no valid root.
        """
        found, a, b, g_a, g_b = self._grid_brackets(rho_p, z_p)
        s = self._illinois(a, b, g_a, g_b, rho_p, z_p)
        _, ok = self.residual(s, rho_p, z_p)
        return np.where(found & ok, s, np.nan)

    def _grid_brackets(
        self, rho_p: NDArray[np.float64], z_p: NDArray[np.float64]
    ) -> tuple[NDArray[np.bool_], NDArray, NDArray, NDArray, NDArray]:
        """Whether each point's grid holds a valid sign change, the first one, and its residuals."""
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
        return found, grid[k], grid[k + 1], g[rows, k], g[rows, k + 1]


class _Table:
    """First guesses of the root on nodes of (direction, inverse distance), bilinear.

    The direction is ``t = tan(theta / 2) = z / (rho + d)`` in ``[-1, 1]``, ``theta`` the
    point's elevation seen from the mirror frame's origin and ``d`` its distance (no arctan);
    the inverse distance ``1 / d`` spans ``[0, 1 / TABLE_NEAR]``.

    Built from ``roots`` ``(A, W)``, the grid search's roots at the nodes, and ``half``
    ``(A - 1, W - 1)``, each cell's bracket half-width (NaN: the grid searches the cell; inf:
    the cell and its neighbours hold no root at any node or middle, so no point in it has one).
    Each cell keeps its bilinear coefficients and half-width in one row, gathered once a point.
    """

    def __init__(self, roots: NDArray[np.float64], half: NDArray[np.float64]) -> None:
        r00, r10, r01, r11 = roots[:-1, :-1], roots[1:, :-1], roots[:-1, 1:], roots[1:, 1:]
        with np.errstate(invalid="ignore"):
            cells = np.stack([r00, r10 - r00, r01 - r00, r11 - r10 - r01 + r00, half], -1)
        self.cells = cells.reshape(-1, 5)
        self.shape = half.shape
        self.d_direction = 2.0 / (TABLE_DIRECTIONS - 1)
        self.d_inverse = 1.0 / TABLE_NEAR / (TABLE_INVERSE - 1)

    def lookup(
        self, rho_p: NDArray[np.float64], z_p: NDArray[np.float64]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Return each point's interpolated root and bracket half-width (NaN, inf: above)."""
        d = np.sqrt(rho_p * rho_p + z_p * z_p)
        u = (z_p / (rho_p + d) + 1.0) / self.d_direction
        v = 1.0 / (d * self.d_inverse)
        inside = (u >= 0.0) & (u < self.shape[0]) & (v < self.shape[1])
        i = np.where(inside, u, 0.0).astype(np.intp)
        j = np.where(inside, v, 0.0).astype(np.intp)
        fu, fv = u - i, v - j
        c = self.cells[i * self.shape[1] + j]
        guess = c[:, 0] + fu * (c[:, 1] + fv * c[:, 3]) + fv * c[:, 2]
        return guess, np.where(inside, c[:, 4], np.nan)


@functools.lru_cache(maxsize=32)
def _first_guess_table(mirror: QuadricMirror, camera_z: float, side: float) -> _Table:
    """Build the table of one mirror and pinhole from the grid search (once, about 0.1 s)."""
    solver = MeridianSolver(mirror, camera_z, side)
    directions = np.linspace(-1.0, 1.0, TABLE_DIRECTIONS)
    inverse = np.linspace(0.0, 1.0 / TABLE_NEAR, TABLE_INVERSE)

    def roots(t: NDArray[np.float64], w: NDArray[np.float64]) -> NDArray[np.float64]:
        # a point at infinity (w = 0) is taken 1e6 m away
        angle = 2.0 * np.arctan(t)
        d = 1.0 / np.maximum(w, 1e-6)
        aa, dd = np.meshgrid(angle, d, indexing="ij")
        rho, z = np.maximum(dd * np.cos(aa), 1e-9), dd * np.sin(aa)
        return solver.grid_solve(rho.ravel(), z.ravel()).reshape(aa.shape)

    at_nodes = roots(directions, inverse)
    at_middles = roots(0.5 * (directions[1:] + directions[:-1]), 0.5 * (inverse[1:] + inverse[:-1]))
    four = np.stack([at_nodes[:-1, :-1], at_nodes[1:, :-1], at_nodes[:-1, 1:], at_nodes[1:, 1:]])
    error = np.abs(0.25 * four.sum(axis=0) - at_middles)
    half = np.maximum(TABLE_MARGIN * error, TABLE_FLOOR)
    # NaN corners or middles, or a bracket wider than half the grid's: the grid searches it
    half[~(half <= 0.5 * mirror.rim_radius / (GRID - 1))] = np.nan
    # no root at a corner or the middle of the cell or of any neighbour: none inside
    rootless = np.isnan(four).all(axis=0) & np.isnan(at_middles)
    padded = np.pad(rootless, 1, constant_values=True)  # nothing lies beyond the table
    a, w = rootless.shape
    empty = np.all(
        [
            padded[1 + di : 1 + di + a, 1 + dj : 1 + dj + w]
            for di in (-1, 0, 1)
            for dj in (-1, 0, 1)
        ],
        axis=0,
    )
    half[empty] = np.inf
    return _Table(at_nodes, half)
