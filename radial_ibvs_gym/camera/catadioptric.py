"""Catadioptric camera: a pinhole on the axis of a quadric mirror, central or non-central.

Exact forward projection (3D point -> pixel) solves the law of reflection in the plane that
holds the mirror axis and the point (:mod:`radial_ibvs_gym.camera.meridian`, a vectorised
bracketed root-find); backward projection
(pixel -> reflected world ray) intersects the pixel's ray with the mirror. Imperfections (a
principal-point offset, a focal-ratio error, pixel noise, a tilt or a sideways offset of the
camera from the mirror axis) are parameters, so robustness studies use the same model.

Frames (see ``docs/conventions.md``): points are given in the *camera frame*, whose origin is the
nominal pinhole on the mirror axis and whose z axis is the mirror axis, pointing up at the
mirror. The mirror frame is the camera frame shifted by ``camera_z`` along z.

About 600 lines, one camera model: the forward and backward projections, visibility and the
imperfections all read the same mirror geometry, and each step cites the equation it
implements.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property, lru_cache
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from radial_ibvs_gym._validation import as_float_array, check_finite, check_last_dim
from radial_ibvs_gym.camera.meridian import MeridianSolver
from radial_ibvs_gym.camera.mirrors import QuadricMirror
from radial_ibvs_gym.camera.pinhole import Intrinsics
from radial_ibvs_gym.geometry import rot_x, rot_y

__all__ = ["CatadioptricCamera", "Imperfections", "Projection"]

#: Samples of the grid that brackets the blind zone's edge.
_GRID = 96


@dataclass(frozen=True, kw_only=True)
class Imperfections:
    """Departures of the real camera from the nominal model, for robustness studies.

    Attributes
    ----------
    principal_point_offset
        ``(du, dv)`` pixels: true principal point minus the nominal one.
    focal_ratio_error
        Relative error of ``fy``: the true ``fy`` is ``fy (1 + focal_ratio_error)``, so the
        nominal ``rho_f`` is wrong by that factor. Must be > -1.
    pixel_noise_std
        Standard deviation of the Gaussian noise added to each pixel coordinate, pixels (>= 0).
    tilt
        ``(about_x, about_y)`` radians: the camera is rotated about its x axis, then about its
        y axis, away from the mirror axis.
    axis_offset
        ``(dx, dy)`` metres: the pinhole is displaced sideways from the mirror axis.
    """

    principal_point_offset: tuple[float, float] = (0.0, 0.0)
    focal_ratio_error: float = 0.0
    pixel_noise_std: float = 0.0
    tilt: tuple[float, float] = (0.0, 0.0)
    axis_offset: tuple[float, float] = (0.0, 0.0)

    def __post_init__(self) -> None:
        for name in ("principal_point_offset", "tilt", "axis_offset"):
            value = getattr(self, name)
            if len(value) != 2 or not all(np.isfinite(v) for v in value):
                raise ValueError(f"{name} must be two finite numbers, got {value!r}")
        if not (np.isfinite(self.focal_ratio_error) and self.focal_ratio_error > -1.0):
            raise ValueError(f"focal_ratio_error must be > -1, got {self.focal_ratio_error!r}")
        if not (np.isfinite(self.pixel_noise_std) and self.pixel_noise_std >= 0.0):
            raise ValueError(f"pixel_noise_std must be >= 0, got {self.pixel_noise_std!r}")

    @cached_property  # read at every step of a vector env, for each robot: computed once
    def any(self) -> bool:
        """True when any imperfection is set (the camera differs from its nominal model)."""
        return self != _NOMINAL

    @cached_property
    def geometric(self) -> bool:
        """True when the camera is tilted or off the mirror axis (the radial model breaks)."""
        return any(v != 0.0 for v in (*self.tilt, *self.axis_offset))


#: the nominal camera: no imperfection (compared with, not rebuilt, by ``Imperfections.any``)
_NOMINAL = Imperfections()


#: The visible rim, the blind radius and the boundary rays of each nominal geometry (mirror,
#: ``camera_z``, lens radius, intrinsics): a vector env rebuilds its cameras every episode, and
#: these root-finds read the nominal geometry only (the 64 latest kept).
_Ray = tuple[float, float, float, float, float]
_LIMITS: dict[tuple[object, ...], tuple[float, float, dict[str, _Ray]]] = {}


@lru_cache(maxsize=64)
def _interned(key: tuple[object, ...]) -> tuple[object, ...]:
    """Return the first of the equal reflection keys seen (cached), so equal keys are one object.

    The cameras of a vector env are rebuilt each episode; with one key object,
    :func:`~radial_ibvs_gym.camera.batch.shares_reflection` compares them by identity.
    """
    return key


class Projection(NamedTuple):
    """Result of :meth:`CatadioptricCamera.forward`.

    Attributes
    ----------
    pixels
        ``(..., N, 2)`` image points in pixels; NaN where the point is not visible.
    mirror_points
        ``(..., N, 3)`` reflection points on the mirror, camera frame, metres; NaN where the
        law of reflection has no solution on the silvered part.
    visible
        ``(..., N)`` booleans (see :meth:`CatadioptricCamera.visible`).
    """

    pixels: NDArray[np.float64]
    mirror_points: NDArray[np.float64]
    visible: NDArray[np.bool_]


def _unit2(x: NDArray[np.float64], z: NDArray[np.float64]) -> tuple[NDArray, NDArray]:
    n = np.hypot(x, z)
    return x / n, z / n


class CatadioptricCamera:
    """A pinhole camera looking up the axis of a rotationally symmetric mirror.

    Parameters
    ----------
    mirror
        The mirror (any :class:`~radial_ibvs_gym.camera.mirrors.QuadricMirror`).
    intrinsics
        The *nominal* intrinsics: what a user believes, and passes to eq. (7). The camera
        projects with the true ones (nominal plus ``imperfections``).
    camera_z
        Pinhole position on the axis in the mirror frame, metres. ``None`` puts it at the
        mirror's focus (central); any other value is non-central.
    imperfections
        Departures from the nominal model; default none.
    lens_radius
        Radius of the camera/lens seen in the mirror, metres: mirror points whose world rays
        would hit it form the blind zone around the axis.

    Raises
    ------
    ValueError
        If the camera sits inside the mirror or on its non-reflective side, the mirror has no
        central position and ``camera_z`` is None, or nothing is visible at all.
    """

    def __init__(
        self,
        mirror: QuadricMirror,
        intrinsics: Intrinsics,
        camera_z: float | None = None,
        imperfections: Imperfections | None = None,
        lens_radius: float = 0.015,
    ) -> None:
        if camera_z is None:
            if mirror.central_camera_z is None:
                raise ValueError(
                    f"{type(mirror).__name__} has no central pinhole position: pass camera_z"
                )
            camera_z = mirror.central_camera_z
        camera_z = float(camera_z)
        if not np.isfinite(camera_z):
            raise ValueError(f"camera_z must be finite, got {camera_z!r}")
        if mirror.concave:
            inside = float(mirror.implicit(0.0, camera_z)) < 0.0
            if not (inside and camera_z < mirror.rim_z):
                raise ValueError(
                    f"camera_z={camera_z!r} m: the camera must be inside the concave mirror, below "
                    f"its rim (z < {mirror.rim_z:.6g} m)"
                )
        elif not camera_z < mirror.vertex_z:
            raise ValueError(
                f"camera_z={camera_z!r} m puts the camera inside or behind the mirror "
                f"(it must be below the vertex, z < {mirror.vertex_z:.6g} m)"
            )
        if not (np.isfinite(lens_radius) and lens_radius >= 0.0):
            raise ValueError(f"lens_radius must be >= 0, got {lens_radius!r}")
        self.mirror = mirror
        self.intrinsics = intrinsics
        self.camera_z = camera_z
        self.imperfections = imperfections if imperfections is not None else Imperfections()
        self.lens_radius = float(lens_radius)
        imp = self.imperfections
        self.true_intrinsics = Intrinsics(
            fx=intrinsics.fx,
            fy=intrinsics.fy * (1.0 + imp.focal_ratio_error),
            mu_x=intrinsics.mu_x + imp.principal_point_offset[0],
            mu_y=intrinsics.mu_y + imp.principal_point_offset[1],
            width=intrinsics.width,
            height=intrinsics.height,
        )
        #: actual camera axes in the nominal camera frame (columns)
        self._R = rot_y(imp.tilt[1]) @ rot_x(imp.tilt[0])
        self._pinhole = np.array([imp.axis_offset[0], imp.axis_offset[1], 0.0])
        self._side = -1.0 if mirror.concave else 1.0
        self._solver = MeridianSolver(mirror, camera_z, self._side)
        #: what fixes the mirror point that reflects a scene point (None: a tilted or shifted
        #: camera); cameras with equal keys share it (camera.batch.forward_batch)
        self._reflection_key = (
            None if imp.geometric else _interned((mirror, camera_z, self.lens_radius, intrinsics))
        )
        t = self.true_intrinsics
        self._true_row = (t.fx, t.fy, t.mu_x, t.mu_y)  # camera.batch reads it
        nominal = (mirror, camera_z, self.lens_radius, intrinsics)
        limits = _LIMITS.get(nominal)
        if limits is None:
            self._r_max = self._image_limited_rim()
            self._r_blind = self._blind_radius()
            if not self._r_blind < self._r_max:
                raise ValueError(
                    f"nothing is visible: the blind zone (lens_radius={lens_radius!r} m) covers "
                    "the whole mirror image"
                )
            limits = (self._r_max, self._r_blind, self._boundary_rays())
            if len(_LIMITS) >= 64:
                _LIMITS.pop(next(iter(_LIMITS)))
            _LIMITS[nominal] = limits
        self._r_max, self._r_blind, self._boundary = limits

    # --- description -------------------------------------------------------------------------
    def __repr__(self) -> str:
        kind = "central" if self.is_central else "non-central"
        return f"CatadioptricCamera({self.mirror!r}, camera_z={self.camera_z:.6g}, {kind})"

    @property
    def is_central(self) -> bool:
        """True for a single-viewpoint configuration: pinhole at the focus, on the axis."""
        cz = self.mirror.central_camera_z
        return (
            cz is not None and abs(cz - self.camera_z) <= 1e-12 and not self.imperfections.geometric
        )

    @property
    def blind_radius(self) -> float:
        """Mirror radius (metres) inside which the mirror shows the camera itself."""
        return self._r_blind

    @property
    def visible_radius(self) -> float:
        """Largest mirror radius (metres) whose image lies inside the image: rim or sensor."""
        return self._r_max

    # --- meridian-plane geometry (nominal, on-axis pinhole) ----------------------------------
    def _meridian(
        self, s: NDArray[np.float64]
    ) -> tuple[NDArray, NDArray, NDArray, NDArray, NDArray, NDArray, NDArray]:
        """Mirror point, normal, unit direction to the camera and world direction at ``s``."""
        r = np.abs(s)
        mz = self.mirror.profile_z(r)
        slope = np.where(s < 0.0, -1.0, 1.0) * self.mirror.profile_slope(r)
        nn = np.sqrt(1.0 + slope * slope)
        nx, nz = slope / nn, -1.0 / nn
        ux, uz = _unit2(-s, self.camera_z - mz)
        dot = ux * nx + uz * nz
        wx, wz = 2.0 * dot * nx - ux, 2.0 * dot * nz - uz  # reflected: towards the scene
        return mz, nx, nz, dot, wx, wz, r

    # --- 3D refinement for a pinhole off the axis --------------------------------------------
    def _offaxis_residual(
        self, uv: NDArray[np.float64], p_m: NDArray[np.float64], c_m: NDArray[np.float64]
    ) -> NDArray[np.float64]:
        """Fermat's principle: the gradient of the path length along the surface, (..., 2)."""
        rho = np.hypot(uv[..., 0], uv[..., 1])
        m = np.concatenate([uv, self.mirror.profile_z(rho)[..., None]], axis=-1)
        slope = self.mirror.profile_slope(rho)
        safe = np.where(rho > 0.0, rho, 1.0)
        dzdu = np.where(rho > 0.0, slope * uv[..., 0] / safe, 0.0)
        dzdv = np.where(rho > 0.0, slope * uv[..., 1] / safe, 0.0)
        uc = c_m - m
        up = p_m - m
        s = uc / np.linalg.norm(uc, axis=-1, keepdims=True)
        s = s + up / np.linalg.norm(up, axis=-1, keepdims=True)
        return np.stack([s[..., 0] + s[..., 2] * dzdu, s[..., 1] + s[..., 2] * dzdv], axis=-1)

    def _refine_offaxis(
        self, m_m: NDArray[np.float64], p_m: NDArray[np.float64]
    ) -> NDArray[np.float64]:
        c_m = self._pinhole + np.array([0.0, 0.0, self.camera_z])
        uv = m_m[..., :2].copy()
        h = 1e-8
        for _ in range(8):
            f0 = self._offaxis_residual(uv, p_m, c_m)
            ju = (self._offaxis_residual(uv + np.array([h, 0.0]), p_m, c_m) - f0) / h
            jv = (self._offaxis_residual(uv + np.array([0.0, h]), p_m, c_m) - f0) / h
            det = ju[..., 0] * jv[..., 1] - jv[..., 0] * ju[..., 1]
            du = (jv[..., 1] * f0[..., 0] - jv[..., 0] * f0[..., 1]) / det
            dv = (-ju[..., 1] * f0[..., 0] + ju[..., 0] * f0[..., 1]) / det
            uv = uv - np.stack([du, dv], axis=-1)
        rho = np.hypot(uv[..., 0], uv[..., 1])
        return np.concatenate([uv, self.mirror.profile_z(rho)[..., None]], axis=-1)

    # --- public API --------------------------------------------------------------------------
    def forward(self, points: ArrayLike, rng: np.random.Generator | None = None) -> Projection:
        """Exact forward projection of 3D points to pixels through the mirror.

        Parameters
        ----------
        points
            ``(..., N, 3)`` points in the camera frame, metres.
        rng
            If given and ``imperfections.pixel_noise_std > 0``, Gaussian pixel noise is drawn
            from it (deterministic under a seeded generator).

        Returns
        -------
        Projection
            Pixels (NaN where not visible), reflection points and the visibility mask.

        Raises
        ------
        ValueError
            For NaN/inf coordinates or a wrong shape. Points without a reflection are not an
            error: they are reported as not visible.
        """
        p = as_float_array(points, "points")
        check_last_dim(p, 3, "points")
        check_finite(p, "points")
        shape = p.shape[:-1]
        flat = p.reshape(-1, 3)
        m_m, p_m = self._reflect(flat)
        q, visible = self._sensor_rays(m_m, p_m)
        with np.errstate(invalid="ignore", divide="ignore"):
            pixels = self.true_intrinsics.project(q[:, :2] / q[:, 2:3])
            visible &= self.true_intrinsics.contains(pixels)
        if rng is not None and self.imperfections.pixel_noise_std > 0.0:
            pixels = pixels + rng.normal(0.0, self.imperfections.pixel_noise_std, pixels.shape)
        pixels = np.where(visible[:, None], pixels, np.nan)
        return Projection(
            pixels=pixels.reshape(*shape, 2),
            mirror_points=(m_m - np.array([0.0, 0.0, self.camera_z])).reshape(*shape, 3),
            visible=visible.reshape(shape),
        )

    def _reflect(
        self, flat: NDArray[np.float64]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Reflection points ``(K, 3)`` of points ``(K, 3)`` (camera frame), mirror frame.

        Returns the reflection points (NaN where none) and the points in the mirror frame.
        Depends on the mirror, ``camera_z`` and the axis offset only, not on the intrinsics.
        """
        rho_p = np.hypot(flat[:, 0], flat[:, 1])
        z_p = flat[:, 2] + self.camera_z
        on_axis = rho_p <= 1e-12
        s = self._solver.solve(np.where(on_axis, 1.0, rho_p), z_p)
        s = np.where(on_axis, np.nan, s)
        safe = np.where(on_axis, 1.0, rho_p)
        m_m = np.stack(
            [s * flat[:, 0] / safe, s * flat[:, 1] / safe, self.mirror.profile_z(np.abs(s))], -1
        )
        p_m = flat + np.array([0.0, 0.0, self.camera_z])
        if any(self.imperfections.axis_offset):
            with np.errstate(invalid="ignore", divide="ignore"):
                m_m = self._refine_offaxis(m_m, p_m)
        return m_m, p_m

    def _sensor_rays(
        self, m_m: NDArray[np.float64], p_m: NDArray[np.float64]
    ) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
        """Reflection points in the actual camera's axes ``(K, 3)``, and their visibility.

        The visibility here is everything but the sensor's bounds: a reflection on the
        silvered part, outside the blind zone, in front of the camera, not occluded.
        """
        found = np.all(np.isfinite(m_m), axis=-1)
        radius = np.hypot(m_m[:, 0], m_m[:, 1])
        m_cam = m_m - np.array([0.0, 0.0, self.camera_z])
        q = (m_cam - self._pinhole) @ self._R  # actual camera coordinates: R^T (m - c)
        with np.errstate(invalid="ignore"):
            visible = (
                found
                & (q[:, 2] > 0.0)
                & (radius >= self._r_blind)
                & (radius <= self.mirror.rim_radius)
            )
        if self.mirror.concave:
            visible &= ~self._occluded(p_m, m_m)
        return q, visible

    def _occluded(self, p_m: NDArray[np.float64], m_m: NDArray[np.float64]) -> NDArray[np.bool_]:
        """Whether the incoming segment P -> M crosses the silvered sheet before M."""
        with np.errstate(invalid="ignore"):
            _, t, hit = self.mirror.intersect_ray(p_m, m_m - p_m)
        return hit & (t < 1.0 - 1e-9)

    def backward(self, pixels: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Backward projection: the reflected world ray of each pixel.

        Parameters
        ----------
        pixels
            ``(..., 2)`` image points in pixels.

        Returns
        -------
        origins
            ``(..., 3)`` reflection points on the mirror, camera frame, metres (NaN where the
            pixel's ray misses the mirror).
        directions
            ``(..., 3)`` unit directions of the reflected rays, towards the scene.
        """
        px = as_float_array(pixels, "pixels")
        check_last_dim(px, 2, "pixels")
        check_finite(px, "pixels")
        x_m = self.true_intrinsics.unproject(px)
        d_actual = np.concatenate([x_m, np.ones_like(x_m[..., :1])], axis=-1)
        d = d_actual @ self._R.T
        d = d / np.linalg.norm(d, axis=-1, keepdims=True)
        origin = self._pinhole + np.array([0.0, 0.0, self.camera_z])
        hit_m, _, hit = self.mirror.intersect_ray(np.broadcast_to(origin, d.shape), d)
        n = self.mirror.normal3(np.where(hit[..., None], hit_m, 0.0))
        r = d - 2.0 * np.sum(d * n, axis=-1, keepdims=True) * n
        origins = hit_m - np.array([0.0, 0.0, self.camera_z])
        directions = np.where(hit[..., None], r, np.nan)
        return origins, directions

    def reflection_angle_error(
        self, points: ArrayLike, mirror_points: ArrayLike
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Check the law of reflection at given reflection points (camera frame).

        Returns
        -------
        angle_error
            ``(...)`` ``|incidence angle - reflection angle|``, radians.
        coplanarity
            ``(...)`` triple product of the unit incident, reflected and normal vectors (zero
            when they are coplanar).
        """
        p_m = as_float_array(points, "points") + np.array([0.0, 0.0, self.camera_z])
        m_m = as_float_array(mirror_points, "mirror_points") + np.array([0, 0, self.camera_z])
        c_m = self._pinhole + np.array([0.0, 0.0, self.camera_z])
        n = self.mirror.normal3(m_m)
        uc = c_m - m_m
        up = p_m - m_m
        uc = uc / np.linalg.norm(uc, axis=-1, keepdims=True)
        up = up / np.linalg.norm(up, axis=-1, keepdims=True)

        def angle(u: NDArray[np.float64]) -> NDArray[np.float64]:
            return np.arctan2(np.linalg.norm(np.cross(u, n), axis=-1), np.sum(u * n, axis=-1))

        triple = np.sum(np.cross(uc, up) * n, axis=-1)
        return np.abs(angle(uc) - angle(up)), triple

    # --- visibility --------------------------------------------------------------------------
    def _image_limited_rim(self) -> float:
        """Largest mirror radius whose image stays inside the sensor (nominal geometry)."""
        k = self.intrinsics
        hx = min(k.mu_x, k.width - 1 - k.mu_x)
        hy = min(k.mu_y, k.height - 1 - k.mu_y)

        def inside(r: NDArray[np.float64]) -> NDArray[np.bool_]:
            z = self.mirror.profile_z(r) - self.camera_z
            return (k.fx * r / z <= hx) & (k.fy * r / z <= hy)

        rim = self.mirror.rim_radius
        if inside(np.array(rim)):
            return rim
        lo, hi = 0.0, rim
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if inside(np.array(mid)) else (lo, mid)
        return lo

    def _blind(self, r: NDArray[np.float64]) -> NDArray[np.bool_]:
        """Whether the world ray reflected at mirror radius ``r`` would hit the lens."""
        s = self._side * r
        mz, _, _, _, wx, wz, _ = self._meridian(s)
        with np.errstate(invalid="ignore", divide="ignore"):
            t = (self.camera_z - mz) / wz
            rho_hit = np.abs(s + t * wx)
        return (wz < 0.0) & (rho_hit <= self.lens_radius)

    def _blind_radius(self) -> float:
        grid = np.linspace(0.0, self._r_max, _GRID)
        blind = self._blind(grid)
        if not blind[0]:
            return 0.0
        k = int(np.argmin(blind))  # first non-blind sample
        if blind[k]:
            return self._r_max
        lo, hi = grid[k - 1], grid[k]
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if self._blind(np.array(mid)) else (lo, mid)
        return hi

    def _boundary_rays(self) -> dict[str, tuple[float, float, float, float, float]]:
        """Return the two limiting world rays and, for each, the side where visible points lie."""
        rays: dict[str, tuple[float, float, float, float]] = {}
        for name, r in (("rim", self._r_max), ("blind", self._r_blind)):
            s_r = np.array(self._side * r)
            mz, *_, wx, wz, _ = self._meridian(s_r)
            rays[name] = (float(s_r), float(mz), float(wx), float(wz))
        mid = np.array(self._side * 0.5 * (self._r_max + self._r_blind))
        mz, *_, wx, wz, _ = self._meridian(mid)
        qx, qz = float(mid + wx), float(mz + wz)  # 1 m along the middle ray: surely visible
        out: dict[str, tuple[float, float, float, float, float]] = {}
        for name, (s, mz_, wx_, wz_) in rays.items():
            ref = np.sign(wx_ * (qz - mz_) - wz_ * (qx - s))
            out[name] = (s, mz_, wx_, wz_, float(ref))
        return out

    def visible(self, points: ArrayLike, *, validate: bool = True) -> NDArray[np.bool_]:
        """Which points the camera sees (cheap: no root-finding for an on-axis camera).

        A point is visible when its reflection lies on the silvered part between the blind
        radius (the camera's own reflection) and the rim (or the sensor's edge), in front of
        the lens and inside the image. For an on-axis camera this is decided by which side of
        the two limiting world rays (reflected at the rim and at the blind radius) the point
        lies on, in the plane holding the axis and the point; for a tilted or off-axis camera
        by the exact :meth:`forward`.

        Parameters
        ----------
        points
            ``(..., N, 3)`` points in the camera frame, metres.
        validate
            Check the shape and finiteness of ``points`` (``False`` skips it on hot paths that
            guarantee them, such as the environments' step).

        Returns
        -------
        numpy.ndarray
            ``(..., N)`` booleans.
        """
        p = np.asarray(points, dtype=np.float64)
        if validate:
            check_last_dim(p, 3, "points")
            check_finite(p, "points")
        if self.imperfections.geometric or self.mirror.concave:
            return self.forward(p).visible
        rho = np.hypot(p[..., 0], p[..., 1])
        z = p[..., 2] + self.camera_z
        ok: NDArray[np.bool_] = rho > 1e-12
        for s, mz, wx, wz, ref in self._boundary.values():
            ok &= (wx * (z - mz) - wz * (rho - s)) * ref > 0.0
        return ok

    def elevation_range(self) -> tuple[float, float]:
        """Vertical field of view: elevations (radians above the horizontal) of the limiting rays.

        Returns
        -------
        tuple of float
            ``(lowest, highest)`` elevation of the world rays reflected at the blind radius and
            at the visible rim. For a central camera these are the elevations seen from the
            single viewpoint; for a non-central one, the directions of the limiting rays.
        """
        angles = [float(np.arctan2(wz, abs(wx))) for _, _, wx, wz, _ in self._boundary.values()]
        return (min(angles), max(angles))

    def visible_radius_bounds(
        self, heights: ArrayLike
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]] | None:
        """Horizontal distances at which points of given heights are visible (on-axis cameras).

        For an on-axis camera and a convex mirror, :meth:`visible` tests two half-planes in the
        ``(rho, z)`` meridian plane, so for a point at a fixed height ``z`` it reduces to an
        interval of ``rho = hypot(x, y)``: the point is visible iff ``lo < rho < hi``. A robot
        moving on the floor sees its landmarks at fixed heights, so the environments compute
        the interval once per episode and visibility costs two comparisons per step.

        Parameters
        ----------
        heights
            ``(...,)`` heights ``z`` of points in the camera frame, metres.

        Returns
        -------
        tuple of numpy.ndarray or None
            ``(lo, hi)``, each ``(...,)`` metres (``hi <= lo`` when no distance is visible,
            ``hi = inf`` when there is no upper bound); ``None`` for a tilted or off-axis
            camera or a concave mirror, where only :meth:`visible` applies.
        """
        if self.imperfections.geometric or self.mirror.concave:
            return None
        z = np.asarray(heights, dtype=np.float64) + self.camera_z
        lo = np.full(z.shape, 1e-12)
        hi = np.full(z.shape, np.inf)
        for s, mz, wx, wz, ref in self._boundary.values():
            # (wx (z - mz) - wz (rho - s)) ref > 0  <=>  k rho + b > 0
            k = -wz * ref
            b = (wx * (z - mz) + wz * s) * ref
            if k > 0.0:
                lo = np.maximum(lo, -b / k)
            elif k < 0.0:
                hi = np.minimum(hi, -b / k)
            else:  # a horizontal limiting ray: all distances or none
                hi = np.where(b > 0.0, hi, -np.inf)
        return lo, hi
