"""Measuring through a real camera: normalised image points as the paper's set-up gets them.

The exact projection through the mirror with the camera's true intrinsics, tilt, offset and
pixel noise, then eq. (7) with the *nominal* principal point and ``rho_f``: what a calibrated,
imperfect camera measures (:func:`camera_image`), for one camera or many at once
(:func:`camera_images`, the same bits row by row). The envs' imperfect cameras call these.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from radial_ibvs_gym._validation import check_finite, check_last_dim
from radial_ibvs_gym.camera.batch import project_rows, project_shared, shares_reflection
from radial_ibvs_gym.camera.catadioptric import CatadioptricCamera, Projection
from radial_ibvs_gym.camera.radial import normalise_pixels, normalise_unchecked

__all__ = ["camera_image", "camera_images", "camera_images_shared"]

Array = NDArray[np.float64]


def camera_image(
    camera: CatadioptricCamera, p_cam: Array, rng: np.random.Generator | None
) -> tuple[Array, NDArray[np.bool_]]:
    """Normalised image points of a real camera, measured as the paper's set-up does.

    Exact projection through the mirror with the true intrinsics, tilt and offset, pixel noise
    from ``rng``, then eq. (7) with the *nominal* principal point and ``rho_f``. An ideal
    concave (self-occluding) mirror is handled exactly without the projection.

    Parameters
    ----------
    camera
        The camera (one env's).
    p_cam
        ``(N, 3)`` landmarks in the camera frame, metres.
    rng
        The env's generator (pixel noise); ``None``: no noise.

    Returns
    -------
    points, visible
        ``(N, 2)`` (zeros where hidden) and ``(N,)``.
    """
    if not camera.imperfections.any:  # an on-axis concave mirror: exact visibility
        visible = camera.visible(p_cam, validate=False)
        d = np.hypot(p_cam[:, 0], p_cam[:, 1])
        return p_cam[:, :2] * (visible / np.maximum(d, 1e-300))[:, None], visible
    proj = camera.forward(p_cam, rng=rng)
    k = camera.intrinsics
    pixels = np.where(proj.visible[:, None], proj.pixels, k.principal_point + 1.0)
    x_n = normalise_pixels(pixels, k.principal_point, k.rho_f)
    return np.where(proj.visible[:, None], x_n, 0.0), proj.visible


def camera_images(
    cameras: Sequence[CatadioptricCamera],
    p_cam: Array,
    rngs: Sequence[np.random.Generator | None],
) -> tuple[Array, NDArray[np.bool_]]:
    """:func:`camera_image` for ``K`` cameras at once, each with its own generator.

    The cameras with imperfections that share the mirror's reflection
    (:func:`~radial_ibvs_gym.camera.batch.shares_reflection`) are projected in one batched
    root-find (:func:`~radial_ibvs_gym.camera.batch.forward_batch`); the result is, row for
    row and bit for bit, what :func:`camera_image` gives each camera.

    Parameters
    ----------
    cameras
        ``K`` cameras (one per env).
    p_cam
        ``(K, N, 3)`` landmarks, row ``k`` in camera ``k``'s frame, metres.
    rngs
        ``K`` generators (pixel noise; ``None``: none).

    Returns
    -------
    points, visible
        ``(K, N, 2)`` (zeros where hidden) and ``(K, N)``.
    """
    if p_cam.ndim != 3 or p_cam.shape[0] != len(cameras) or len(rngs) != len(cameras):
        raise ValueError(
            f"p_cam must have shape ({len(cameras)}, N, 3) with {len(cameras)} generators, got "
            f"{p_cam.shape} and {len(rngs)}"
        )
    check_last_dim(p_cam, 3, "p_cam")
    check_finite(p_cam, "p_cam")
    k, n = p_cam.shape[:2]
    points = np.zeros((k, n, 2))
    visible = np.zeros((k, n), dtype=bool)
    batched = [i for i, c in enumerate(cameras) if c.imperfections.any]
    for i in sorted(set(range(k)) - set(batched)):
        points[i], visible[i] = camera_image(cameras[i], p_cam[i], rngs[i])
    group = [cameras[i] for i in batched]
    if len(group) < 2 or not shares_reflection(group):
        for i in batched:
            points[i], visible[i] = camera_image(cameras[i], p_cam[i], rngs[i])
        return points, visible
    every = len(batched) == k
    proj = project_shared(
        group, p_cam if every else p_cam[batched], rngs if every else [rngs[i] for i in batched]
    )
    x_n = _normalised(group[0], proj)
    if every:
        return x_n, proj.visible
    points[batched] = x_n
    visible[batched] = proj.visible
    return points, visible


def camera_images_shared(
    first: CatadioptricCamera,
    rows: Array,
    p_cam: Array,
    stds: Array,
    normals: Array | None,
) -> tuple[Array, NDArray[np.bool_]]:
    """:func:`camera_images` for cameras kept as arrays, which share ``first``'s reflection.

    What a vector env calls at each step: its cameras' true intrinsics and noise levels held
    in arrays over its episodes, the noise drawn by the env
    (:class:`~radial_ibvs_gym.envs.noise_blocks.NoiseBlocks`). Row for row and bit for bit,
    :func:`camera_image` of each camera with that noise. Unchecked: every camera has
    imperfections and shares ``first``'s reflection
    (:func:`~radial_ibvs_gym.camera.batch.shares_reflection`), the points are finite.

    Parameters
    ----------
    first
        One of the cameras.
    rows
        ``(K, 4)`` each camera's true ``(fx, fy, mu_x, mu_y)``, pixels
        (:func:`~radial_ibvs_gym.camera.batch.true_rows`).
    p_cam
        ``(K, N, 3)`` landmarks, row ``k`` in camera ``k``'s frame, metres.
    stds
        ``(K,)`` each camera's pixel noise standard deviation, pixels.
    normals
        ``(K, N, 2)`` standard normal draws, zeros where ``stds`` is 0; ``None``: no noise.

    Returns
    -------
    points, visible
        ``(K, N, 2)`` (zeros where hidden) and ``(K, N)``.
    """
    proj = project_rows(first, rows, p_cam, stds, normals)
    return _normalised(first, proj), proj.visible


def _normalised(first: CatadioptricCamera, proj: Projection) -> Array:
    """Eq. (7) with the nominal intrinsics (shared by the group); zeros where hidden."""
    nominal = first.intrinsics
    centre = np.asarray(nominal.principal_point, dtype=np.float64)
    shown = proj.visible[..., None]
    pixels = np.where(shown, proj.pixels, centre + 1.0)
    return np.where(shown, normalise_unchecked(pixels, centre, nominal.rho_f), 0.0)
