"""Checks of the radial model on a real camera: eq. (7) on projected pixels against eq. (9).

Pure numpy: what a user of :mod:`radial_ibvs_gym.camera` needs to see how far an imperfect
camera departs from the radial model, and where the mirror's circles fall in the image.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from radial_ibvs_gym._validation import as_float_array, check_last_dim
from radial_ibvs_gym.camera.catadioptric import CatadioptricCamera
from radial_ibvs_gym.camera.radial import normalise_pixels, radial_points

__all__ = ["invariance_errors", "mirror_circle_pixels"]


def invariance_errors(
    camera: CatadioptricCamera,
    points_cam: ArrayLike,
    principal_point: ArrayLike | None = None,
    rho_f: float | None = None,
    rng: np.random.Generator | None = None,
) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Point-by-point ``|x_n(eq. 7 on the projected pixels) - x_n(eq. 9 on the 3D points)|``.

    The camera projects the points exactly (:meth:`CatadioptricCamera.forward`, with its true
    intrinsics and imperfections); eq. (7) then normalises the pixels with the principal point
    and focal ratio a user believes (the camera's nominal ones unless given).

    Parameters
    ----------
    camera
        The camera that projects the points.
    points_cam
        ``(N, 3)`` points in the camera frame, metres.
    principal_point
        ``(2,)`` principal point used by eq. (7), pixels. Default: the nominal one.
    rho_f
        Focal ratio ``fx / fy`` used by eq. (7). Default: the nominal one.
    rng
        Generator of the pixel noise, if the camera has some (``Imperfections.pixel_noise_std``).

    Returns
    -------
    errors
        ``(K,)`` distances on the unit circle (dimensionless; for small values, the angle error
        in radians) of the ``K`` visible points.
    visible
        ``(N,)`` mask of the visible points (the rows of ``errors``).
    """
    p = as_float_array(points_cam, "points_cam")
    check_last_dim(p, 3, "points_cam")
    k = camera.intrinsics
    mu = (
        k.principal_point
        if principal_point is None
        else as_float_array(principal_point, "principal_point")
    )
    ratio = k.rho_f if rho_f is None else float(rho_f)
    proj = camera.forward(p, rng=rng)
    visible = np.asarray(proj.visible, dtype=bool)
    if not np.any(visible):
        return np.zeros(0), visible
    from_pixels = normalise_pixels(proj.pixels[visible], mu, ratio)
    from_points = radial_points(p[visible], sign=camera.mirror.radial_sign).x_n
    return np.linalg.norm(from_pixels - from_points, axis=-1), visible


def mirror_circle_pixels(
    camera: CatadioptricCamera, radius: float, n: int = 181
) -> NDArray[np.float64]:
    """Pixels of the circle of a given radius on the mirror (nominal on-axis geometry).

    Parameters
    ----------
    camera
        The camera.
    radius
        Radius on the mirror, metres (e.g. ``camera.visible_radius`` for the rim,
        ``camera.blind_radius`` for the blind zone).
    n
        Number of points of the closed polygon (first and last coincide).

    Returns
    -------
    numpy.ndarray
        ``(n, 2)`` pixels ``(u, v)``.
    """
    phi = np.linspace(0.0, 2.0 * np.pi, int(n))
    z = float(camera.mirror.profile_z(radius)) - camera.camera_z
    x_m = np.stack([radius * np.cos(phi), radius * np.sin(phi)], axis=-1) / z
    return camera.intrinsics.project(x_m)
