"""Small helpers for the teaching notebooks on the camera (``notebooks/01_*``, ``02_*``).

The notebooks import and call these; they hold no library logic of their own. Two groups
(the finite differences of the features are in :mod:`_helpers.teaching_interaction`):

- sampling and measuring: :func:`sample_scene_points`, :func:`invariance_errors` (eq. 7
  against eq. 9, point by point), :func:`axis_crossings` and :func:`meridian_fan` (where the
  reflected rays of a central or non-central camera cross the mirror axis);
- drawing on a given matplotlib ``Axes`` (matplotlib itself is never imported here):
  :func:`plot_mirror_rays`, :func:`plot_ray_fan`, :func:`plot_image_frame`.

Frames and units as everywhere in the package (``docs/conventions.md``): the camera frame has
its origin at the nominal pinhole, z along the mirror axis pointing up at the mirror, x
forward; metres, radians, pixels. Drawings of the mirrors are in millimetres.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from radial_ibvs_gym._validation import as_float_array, check_finite, check_last_dim
from radial_ibvs_gym.camera import CatadioptricCamera, invariance_errors, mirror_circle_pixels

if TYPE_CHECKING:
    from matplotlib.axes import Axes

__all__ = [
    "axis_crossings",
    "invariance_errors",
    "meridian_fan",
    "mirror_circle_pixels",
    "plot_image_frame",
    "plot_mirror_rays",
    "plot_ray_fan",
    "sample_scene_points",
]

#: Fraction of the visible mirror annulus kept away from its edges by :func:`meridian_fan`
#: (a ray exactly at the rim may miss the mirror by rounding).
_EDGE = 1e-3


# --- sampling and measuring -----------------------------------------------------------------


def sample_scene_points(
    rng: np.random.Generator,
    n: int,
    distance: tuple[float, float] = (0.5, 8.0),
    height: tuple[float, float] = (-1.8, 1.0),
) -> NDArray[np.float64]:
    """Random 3D points around the camera, in the camera frame.

    Azimuths are uniform in ``[-pi, pi)``, horizontal distances ``d`` uniform in ``distance``
    and heights ``Z`` uniform in ``height`` (relative to the pinhole: ``-1.8`` is the floor
    for a camera 1.8 m above it).

    Parameters
    ----------
    rng
        Seeded generator (the result is deterministic for a given seed).
    n
        Number of points (>= 1).
    distance
        ``(low, high)`` horizontal distances ``sqrt(X^2 + Y^2)``, metres, ``0 < low <= high``.
    height
        ``(low, high)`` heights ``Z``, metres.

    Returns
    -------
    numpy.ndarray
        ``(n, 3)`` points ``(X, Y, Z)``, metres.

    Raises
    ------
    ValueError
        If ``n < 1`` or a range is empty or (for ``distance``) not positive.
    """
    if int(n) < 1:
        raise ValueError(f"n must be >= 1, got {n!r}")
    if not 0.0 < distance[0] <= distance[1]:
        raise ValueError(f"distance must be (low, high) with 0 < low <= high, got {distance!r}")
    if not height[0] <= height[1]:
        raise ValueError(f"height must be (low, high) with low <= high, got {height!r}")
    d = rng.uniform(distance[0], distance[1], int(n))
    azimuth = rng.uniform(-np.pi, np.pi, int(n))
    z = rng.uniform(height[0], height[1], int(n))
    return np.stack([d * np.cos(azimuth), d * np.sin(azimuth), z], axis=-1)


def axis_crossings(
    origins: ArrayLike, directions: ArrayLike
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Where the lines carrying rays come closest to the z axis (the mirror axis).

    A ray ``o + t w`` reflected by a mirror of revolution lies in a plane through the axis, so
    its line meets the axis. For a central camera all reflected rays, extended backwards,
    meet it at one point (the single viewpoint, the mirror's inner focus); for a non-central
    camera the crossing heights spread out (a caustic).

    Parameters
    ----------
    origins
        ``(..., 3)`` points on the rays (e.g. reflection points), metres.
    directions
        ``(..., 3)`` ray directions (any length, non-vertical).

    Returns
    -------
    z
        ``(...)`` height of the closest approach to the axis, metres (same frame as
        ``origins``).
    miss
        ``(...)`` distance from the axis at that point, metres (0 for rays in a plane through
        the axis).

    Raises
    ------
    ValueError
        For shapes other than ``(..., 3)``, NaN/inf, or a vertical direction.
    """
    o = as_float_array(origins, "origins")
    w = as_float_array(directions, "directions")
    check_last_dim(o, 3, "origins")
    check_last_dim(w, 3, "directions")
    check_finite(o, "origins")
    check_finite(w, "directions")
    horizontal = w[..., 0] ** 2 + w[..., 1] ** 2
    if np.any(horizontal <= 1e-300):
        raise ValueError("a direction is vertical: its line never approaches the axis")
    t = -(o[..., 0] * w[..., 0] + o[..., 1] * w[..., 1]) / horizontal
    closest = o + t[..., None] * w
    return closest[..., 2], np.hypot(closest[..., 0], closest[..., 1])


def meridian_fan(
    camera: CatadioptricCamera, n_rays: int
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Backward-project pixels along the ``+u`` image axis: a fan of rays in the x-z plane.

    The pixels go from the image of the blind radius to the image of the visible rim (kept a
    hair inside both), on the row of the principal point, so for an on-axis camera every ray
    lies in the meridian plane ``y = 0`` with ``x > 0``.

    Parameters
    ----------
    camera
        The camera (its true intrinsics are used, as by :meth:`~CatadioptricCamera.backward`).
    n_rays
        Number of rays (>= 2).

    Returns
    -------
    origins
        ``(n_rays, 3)`` reflection points on the mirror, camera frame, metres.
    directions
        ``(n_rays, 3)`` unit directions of the reflected rays, towards the scene.

    Raises
    ------
    ValueError
        If ``n_rays < 2``.
    """
    if int(n_rays) < 2:
        raise ValueError(f"n_rays must be >= 2, got {n_rays!r}")
    k = camera.true_intrinsics
    span = camera.visible_radius - camera.blind_radius
    radii = np.linspace(
        camera.blind_radius + _EDGE * span, camera.visible_radius - _EDGE * span, int(n_rays)
    )
    depth = camera.mirror.profile_z(radii) - camera.camera_z
    pixels = np.stack([k.mu_x + k.fx * radii / depth, np.full_like(radii, k.mu_y)], axis=-1)
    return camera.backward(pixels)


# --- drawing (on a given Axes; millimetres for the mirrors) ---------------------------------


def _profile(camera: CatadioptricCamera, n: int = 201) -> tuple[NDArray, NDArray]:
    """Meridian section of the silvered part: signed radius and height, camera frame, metres."""
    rho = np.linspace(-camera.mirror.rim_radius, camera.mirror.rim_radius, n)
    return rho, camera.mirror.profile_z(np.abs(rho)) - camera.camera_z


def plot_mirror_rays(
    ax: Axes,
    camera: CatadioptricCamera,
    points_cam: ArrayLike,
    *,
    color: str = "C0",
    label: str | None = None,
    ray_length: float = 0.04,
    scale: float = 1e3,
) -> int:
    """Draw a mirror's meridian section to scale and the light paths of scene points.

    Each visible point is drawn in its own meridian plane (the plane through the axis and the
    point), turned onto the ``+rho`` side: the ray from the mirror to the pinhole (solid) and
    the reflected ray towards the scene point (dashed, ``ray_length`` long).

    Parameters
    ----------
    ax
        Matplotlib axes.
    camera
        The camera (on-axis: its reflection points are in the meridian plane of each point).
    points_cam
        ``(N, 3)`` scene points in the camera frame, metres.
    color
        Matplotlib colour of the mirror and the rays.
    label
        Legend label of the mirror.
    ray_length
        Drawn length of the reflected rays, metres.
    scale
        Drawing units per metre (``1e3``: millimetres).

    Returns
    -------
    int
        Number of points drawn (the visible ones).
    """
    p = as_float_array(points_cam, "points_cam")
    check_last_dim(p, 3, "points_cam")
    rho, z = _profile(camera)
    ax.plot(scale * rho, scale * z, color=color, lw=2, label=label)
    proj = camera.forward(p)
    drawn = 0
    for point, mirror_point, seen in zip(p, proj.mirror_points, proj.visible, strict=True):
        if not seen:
            continue
        r_m, z_m = float(np.hypot(*mirror_point[:2])), float(mirror_point[2])
        direction = np.array([np.hypot(*point[:2]) - r_m, point[2] - z_m])
        far = np.array([r_m, z_m]) + ray_length * direction / np.linalg.norm(direction)
        ax.plot(scale * np.array([0.0, r_m]), scale * np.array([0.0, z_m]), color=color, lw=0.8)
        ax.plot(
            scale * np.array([r_m, far[0]]),
            scale * np.array([z_m, far[1]]),
            color=color,
            lw=0.8,
            ls="--",
        )
        drawn += 1
    ax.plot(0.0, 0.0, "k^", ms=8)
    ax.set_aspect("equal")
    return drawn


def plot_ray_fan(
    ax: Axes,
    camera: CatadioptricCamera,
    n_rays: int = 9,
    *,
    color: str = "C0",
    ray_length: float = 0.03,
    scale: float = 1e3,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Draw a fan of reflected rays in the meridian plane, with their backward extensions.

    Uses :func:`meridian_fan`: pixels along the image's ``+u`` axis are back-projected; each
    light path is drawn from the pinhole to the mirror (thin solid), then out to the scene
    (solid, ``ray_length`` long), and its line is extended behind the mirror to the axis
    (dotted). A central camera's extensions meet at one point; a non-central one's do not.

    Parameters
    ----------
    ax
        Matplotlib axes.
    camera
        The camera (on-axis).
    n_rays
        Number of rays (>= 2).
    color
        Matplotlib colour.
    ray_length
        Drawn length of the reflected rays, metres.
    scale
        Drawing units per metre (``1e3``: millimetres).

    Returns
    -------
    z
        ``(n_rays,)`` heights where the extended rays cross the axis, metres, camera frame
        (see :func:`axis_crossings`).
    miss
        ``(n_rays,)`` their distances from the axis there, metres (0 up to rounding).
    """
    origins, directions = meridian_fan(camera, n_rays)
    z_cross, miss = axis_crossings(origins, directions)
    rho, z = _profile(camera)
    ax.plot(scale * rho, scale * z, color="0.3", lw=2)
    for o, w, zc in zip(origins, directions, z_cross, strict=True):
        far = o + ray_length * w
        ax.plot(scale * np.array([0.0, o[0]]), scale * np.array([0.0, o[2]]), color=color, lw=0.5)
        ax.plot(scale * np.array([o[0], far[0]]), scale * np.array([o[2], far[2]]), color=color)
        ax.plot(scale * np.array([o[0], 0.0]), scale * np.array([o[2], zc]), color=color, ls=":")
    ax.plot(0.0, 0.0, "k^", ms=8)
    ax.set_aspect("equal")
    return z_cross, miss


def plot_image_frame(ax: Axes, camera: CatadioptricCamera) -> None:
    """Draw the sensor, the image of the mirror's visible rim and the blind zone, in pixels.

    The axes get image conventions: ``u`` to the right, ``v`` down, equal aspect.

    Parameters
    ----------
    ax
        Matplotlib axes.
    camera
        The camera (its nominal intrinsics and on-axis geometry).
    """
    k = camera.intrinsics
    ax.fill([0, k.width, k.width, 0], [0, 0, k.height, k.height], fc="0.15", ec="k", label="sensor")
    rim = mirror_circle_pixels(camera, camera.visible_radius)
    ax.fill(rim[:, 0], rim[:, 1], fc="0.88", ec="0.4", lw=1.5, label="mirror (visible rim)")
    blind = mirror_circle_pixels(camera, camera.blind_radius)
    ax.fill(blind[:, 0], blind[:, 1], fc="0.35", ec="none", label="blind zone (the lens)")
    ax.plot(k.mu_x, k.mu_y, "+", color="C1", ms=12, mew=2, label="principal point")
    ax.set_xlim(0, k.width)
    ax.set_ylim(k.height, 0)
    ax.set_aspect("equal")
    ax.set_xlabel("u [px]")
    ax.set_ylabel("v [px]")
