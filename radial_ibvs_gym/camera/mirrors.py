"""Rotationally symmetric quadric mirrors (hyperboloid, ellipsoid, paraboloid, sphere, cone).

Every mirror is a quadric of revolution about the z axis of its own *mirror frame*,
``Q(rho, z) = rho^2 + A z^2 + B z + C = 0`` with ``rho = sqrt(x^2 + y^2)``, of which one part is
silvered: the sheet ``z = f(rho)``, ``0 <= rho <= rim_radius``. The camera looks at it from below
(``z < f(0)``), along +z. All lengths in metres.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from radial_ibvs_gym._validation import check_positive

__all__ = ["Cone", "Ellipsoid", "Hyperboloid", "Paraboloid", "QuadricMirror", "Sphere"]


@dataclass(frozen=True, kw_only=True)
class QuadricMirror:
    """Base class of the mirrors: a quadric of revolution with one silvered sheet.

    Subclasses define the profile ``f``, its slope ``f'``, the quadric coefficients and where a
    pinhole must sit for a single viewpoint.

    Attributes
    ----------
    rim_radius
        Radius of the mirror's rim (half its diameter), metres.
    """

    rim_radius: float

    def __post_init__(self) -> None:
        check_positive(self.rim_radius, "rim_radius")

    # --- to override -------------------------------------------------------------------------
    @property
    def coefficients(self) -> tuple[float, float, float]:
        """``(A, B, C)`` of ``rho^2 + A z^2 + B z + C = 0`` (``B`` in metres, ``C`` in m^2)."""
        raise NotImplementedError

    def profile_z(self, rho: ArrayLike) -> NDArray[np.float64]:
        """Height ``z = f(rho)`` of the silvered sheet at radius ``rho`` (metres, any shape)."""
        raise NotImplementedError

    def profile_slope(self, rho: ArrayLike) -> NDArray[np.float64]:
        """Slope ``dz/drho = f'(rho)`` of the silvered sheet (dimensionless, any shape)."""
        raise NotImplementedError

    def profile(self, rho: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Return the height (metres) and slope of the sheet at ``rho``, as the two methods do.

        The same values, bit for bit; a mirror may share their common terms (a root-find
        evaluates both at every iteration).
        """
        return self.profile_z(rho), self.profile_slope(rho)

    @property
    def central_camera_z(self) -> float | None:
        """On-axis pinhole position (mirror frame, metres) giving a single viewpoint, or None."""
        return None

    @property
    def concave(self) -> bool:
        """True when the camera sees the inside (concave side) of the mirror."""
        return False

    # --- shared ------------------------------------------------------------------------------
    @property
    def radial_sign(self) -> int:
        """+1 if a scene point's image lies on its side of the axis (convex), -1 if opposite."""
        return -1 if self.concave else 1

    def implicit(self, rho: ArrayLike, z: ArrayLike) -> NDArray[np.float64]:
        """``Q(rho, z) = rho^2 + A z^2 + B z + C`` (m^2; zero on the quadric)."""
        a, b, c = self.coefficients
        r = np.asarray(rho, dtype=np.float64)
        zz = np.asarray(z, dtype=np.float64)
        return np.asarray(r * r + a * zz * zz + b * zz + c, dtype=np.float64)

    def normal(self, rho: ArrayLike) -> NDArray[np.float64]:
        """Return the unit normal in the meridian plane, ``(..., 2)`` as ``(n_rho, n_z)``.

        It points to the silvered (reflective) side, which faces the camera below: for a
        signed radius ``rho < 0`` (the other half of the meridian plane) ``n_rho`` flips sign.
        """
        r = np.asarray(rho, dtype=np.float64)
        slope = np.where(r < 0.0, -1.0, 1.0) * self.profile_slope(np.abs(r))
        norm = np.sqrt(1.0 + slope * slope)
        return np.stack([slope / norm, -1.0 / norm], axis=-1)

    def normal3(self, points: NDArray[np.float64]) -> NDArray[np.float64]:
        """Return unit normals ``(..., 3)`` (reflective side) at mirror-frame points."""
        rho = np.hypot(points[..., 0], points[..., 1])
        slope = self.profile_slope(rho)
        safe = np.where(rho > 0.0, rho, 1.0)
        gx = np.where(rho > 0.0, slope * points[..., 0] / safe, 0.0)
        gy = np.where(rho > 0.0, slope * points[..., 1] / safe, 0.0)
        n = np.stack([gx, gy, -np.ones_like(gx)], axis=-1)
        return n / np.linalg.norm(n, axis=-1, keepdims=True)

    @property
    def vertex_z(self) -> float:
        """Height of the mirror on its axis, ``f(0)``, metres."""
        return float(self.profile_z(0.0))

    @property
    def rim_z(self) -> float:
        """Height of the rim, ``f(rim_radius)``, metres."""
        return float(self.profile_z(self.rim_radius))

    def on_silvered_part(self, points: NDArray[np.float64], tol: float = 1e-9) -> NDArray[np.bool_]:
        """Whether mirror-frame points ``(..., 3)`` on the quadric lie on the silvered sheet."""
        rho = np.hypot(points[..., 0], points[..., 1])
        inside = rho <= self.rim_radius * (1.0 + 1e-12)
        zf = self.profile_z(np.minimum(rho, self.rim_radius))
        return inside & (np.abs(points[..., 2] - zf) <= tol * (1.0 + np.abs(zf)) + 1e-12)

    def intersect_ray(
        self, origins: ArrayLike, directions: ArrayLike
    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_]]:
        """First intersection of rays with the silvered sheet (mirror frame).

        Parameters
        ----------
        origins
            ``(..., 3)`` ray origins, metres.
        directions
            ``(..., 3)`` ray directions (any length).

        Returns
        -------
        points
            ``(..., 3)`` hit points (NaN where the ray misses the silvered sheet), metres.
        t
            ``(...)`` ray parameters of the hits (NaN where missed).
        hit
            ``(...)`` boolean mask.
        """
        o = np.asarray(origins, dtype=np.float64)
        d = np.asarray(directions, dtype=np.float64)
        a_, b_, c_ = self.coefficients
        qa = d[..., 0] ** 2 + d[..., 1] ** 2 + a_ * d[..., 2] ** 2
        qb = 2.0 * (o[..., 0] * d[..., 0] + o[..., 1] * d[..., 1] + a_ * o[..., 2] * d[..., 2])
        qb = qb + b_ * d[..., 2]
        qc = o[..., 0] ** 2 + o[..., 1] ** 2 + a_ * o[..., 2] ** 2 + b_ * o[..., 2] + c_
        best = np.full(qa.shape, np.inf)
        with np.errstate(invalid="ignore", divide="ignore"):
            disc = qb * qb - 4.0 * qa * qc
            sq = np.sqrt(np.where(disc >= 0.0, disc, np.nan))
            linear = np.abs(qa) < 1e-14 * (np.abs(qb) + np.abs(qc) + 1.0)
            # numerically stable roots of the quadratic; the linear case when qa ~ 0
            q = -0.5 * (qb + np.copysign(sq, qb))
            roots = (
                np.where(linear, -qc / qb, q / qa),
                np.where(linear, np.nan, qc / q),
            )
            for t in roots:
                p = o + t[..., None] * d
                ok = np.isfinite(t) & (t > 1e-12) & self.on_silvered_part(p, tol=1e-7)
                best = np.where(ok & (t < best), t, best)
        hit = np.isfinite(best)
        t_hit = np.where(hit, best, np.nan)
        pts = o + t_hit[..., None] * d
        return pts, t_hit, hit


@dataclass(frozen=True, kw_only=True)
class Hyperboloid(QuadricMirror):
    """Hyperboloid ``(x^2 + y^2)/a^2 - z^2/b^2 = -1`` (a radial, b axial), upper sheet.

    The silvered sheet ``z = b sqrt(1 + rho^2/a^2)`` is convex towards the camera. Foci at
    ``z = +-e``, ``e = sqrt(a^2 + b^2)``; a pinhole at the outer focus ``z = -e`` makes the
    system central (every reflected ray passes through the inner focus ``z = +e``).

    Parameters
    ----------
    a, b
        Semi-axes in metres (> 0).
    rim_radius
        Rim radius in metres.
    """

    a: float
    b: float

    def __post_init__(self) -> None:
        super().__post_init__()
        check_positive(self.a, "a")
        check_positive(self.b, "b")

    @property
    def e(self) -> float:
        """Focal half-distance ``sqrt(a^2 + b^2)``, metres."""
        return math.hypot(self.a, self.b)

    @property
    def coefficients(self) -> tuple[float, float, float]:  # noqa: D102
        return (-(self.a**2) / self.b**2, 0.0, self.a**2)

    def profile_z(self, rho: ArrayLike) -> NDArray[np.float64]:  # noqa: D102
        r = np.asarray(rho, dtype=np.float64)
        return self.b * np.sqrt(1.0 + (r / self.a) ** 2)

    def profile_slope(self, rho: ArrayLike) -> NDArray[np.float64]:  # noqa: D102
        r = np.asarray(rho, dtype=np.float64)
        return (self.b / self.a**2) * r / np.sqrt(1.0 + (r / self.a) ** 2)

    def profile(self, rho: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:  # noqa: D102
        r = np.asarray(rho, dtype=np.float64)
        root = np.sqrt(1.0 + (r / self.a) ** 2)  # one square root for both
        return self.b * root, (self.b / self.a**2) * r / root

    @property
    def central_camera_z(self) -> float:  # noqa: D102
        return -self.e


@dataclass(frozen=True, kw_only=True)
class Ellipsoid(QuadricMirror):
    """Prolate ellipsoid ``(x^2 + y^2)/a^2 + z^2/b^2 = 1`` (``b > a``), used concave.

    The silvered sheet is the upper cap ``z = b sqrt(1 - rho^2/a^2)``, seen from inside. Foci at
    ``z = +-sqrt(b^2 - a^2)``; a pinhole at the lower focus makes the system central. The image
    is point-reflected through the principal point (``radial_sign = -1``).

    Parameters
    ----------
    a, b
        Semi-axes in metres, ``0 < a < b``.
    rim_radius
        Rim radius in metres, ``< a``.
    """

    a: float
    b: float

    def __post_init__(self) -> None:
        super().__post_init__()
        check_positive(self.a, "a")
        check_positive(self.b, "b")
        if not self.b > self.a:
            raise ValueError(f"ellipsoid needs b > a (prolate), got a={self.a!r}, b={self.b!r}")
        if not self.rim_radius < self.a:
            raise ValueError(
                f"rim_radius={self.rim_radius!r} must be smaller than a={self.a!r} for an ellipsoid"
            )

    @property
    def coefficients(self) -> tuple[float, float, float]:  # noqa: D102
        return (self.a**2 / self.b**2, 0.0, -(self.a**2))

    def profile_z(self, rho: ArrayLike) -> NDArray[np.float64]:  # noqa: D102
        r = np.asarray(rho, dtype=np.float64)
        return self.b * np.sqrt(np.maximum(1.0 - (r / self.a) ** 2, 0.0))

    def profile_slope(self, rho: ArrayLike) -> NDArray[np.float64]:  # noqa: D102
        r = np.asarray(rho, dtype=np.float64)
        return -(self.b / self.a**2) * r / np.sqrt(np.maximum(1.0 - (r / self.a) ** 2, 1e-300))

    @property
    def central_camera_z(self) -> float:  # noqa: D102
        return -math.sqrt(self.b**2 - self.a**2)

    @property
    def concave(self) -> bool:  # noqa: D102
        return True


@dataclass(frozen=True, kw_only=True)
class Paraboloid(QuadricMirror):
    """Paraboloid ``z = rho^2 / (4 f) - f`` with its focus at the origin, convex to the camera.

    Central only with an orthographic camera; with a pinhole it is always non-central.

    Parameters
    ----------
    focal_length
        ``f`` in metres (> 0): distance from the vertex to the focus.
    rim_radius
        Rim radius in metres.
    """

    focal_length: float

    def __post_init__(self) -> None:
        super().__post_init__()
        check_positive(self.focal_length, "focal_length")

    @property
    def coefficients(self) -> tuple[float, float, float]:  # noqa: D102
        f = self.focal_length
        return (0.0, -4.0 * f, -4.0 * f * f)

    def profile_z(self, rho: ArrayLike) -> NDArray[np.float64]:  # noqa: D102
        r = np.asarray(rho, dtype=np.float64)
        return r * r / (4.0 * self.focal_length) - self.focal_length

    def profile_slope(self, rho: ArrayLike) -> NDArray[np.float64]:  # noqa: D102
        return np.asarray(rho, dtype=np.float64) / (2.0 * self.focal_length)


@dataclass(frozen=True, kw_only=True)
class Sphere(QuadricMirror):
    """Sphere of radius ``R`` centred at the origin; the lower cap ``z = -sqrt(R^2 - rho^2)``.

    Convex towards the camera; non-central for any pinhole position but the centre.

    Parameters
    ----------
    radius
        ``R`` in metres (> 0).
    rim_radius
        Rim radius in metres, ``< R``.
    """

    radius: float

    def __post_init__(self) -> None:
        super().__post_init__()
        check_positive(self.radius, "radius")
        if not self.rim_radius < self.radius:
            raise ValueError(
                f"rim_radius={self.rim_radius!r} must be smaller than the sphere radius "
                f"{self.radius!r}"
            )

    @property
    def coefficients(self) -> tuple[float, float, float]:  # noqa: D102
        return (1.0, 0.0, -(self.radius**2))

    def profile_z(self, rho: ArrayLike) -> NDArray[np.float64]:  # noqa: D102
        r = np.asarray(rho, dtype=np.float64)
        return -np.sqrt(np.maximum(self.radius**2 - r * r, 0.0))

    def profile_slope(self, rho: ArrayLike) -> NDArray[np.float64]:  # noqa: D102
        r = np.asarray(rho, dtype=np.float64)
        return r / np.sqrt(np.maximum(self.radius**2 - r * r, 1e-300))


@dataclass(frozen=True, kw_only=True)
class Cone(QuadricMirror):
    """Cone with its apex at the origin pointing down: ``z = rho / tan(half_angle)``.

    Convex towards the camera; the apex is a degenerate viewpoint, so always non-central.

    Parameters
    ----------
    half_angle
        Angle between the axis and the surface, radians, in ``(0, pi/2)``.
    rim_radius
        Rim radius in metres.
    """

    half_angle: float

    def __post_init__(self) -> None:
        super().__post_init__()
        check_positive(self.half_angle, "half_angle")
        if not self.half_angle < math.pi / 2:
            raise ValueError(f"half_angle must be in (0, pi/2) rad, got {self.half_angle!r}")

    @property
    def coefficients(self) -> tuple[float, float, float]:  # noqa: D102
        return (-(math.tan(self.half_angle) ** 2), 0.0, 0.0)

    def profile_z(self, rho: ArrayLike) -> NDArray[np.float64]:  # noqa: D102
        return np.asarray(rho, dtype=np.float64) / math.tan(self.half_angle)

    def profile_slope(self, rho: ArrayLike) -> NDArray[np.float64]:  # noqa: D102
        r = np.asarray(rho, dtype=np.float64)
        return np.full_like(r, 1.0 / math.tan(self.half_angle))
