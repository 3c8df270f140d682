"""Exact projection for many cameras at once: one mirror, per-camera intrinsics and noise.

A vector env with imperfect cameras holds one camera per robot: the same mirror and pinhole
position, but each with its own principal-point offset, focal-ratio error and pixel noise
(drawn per episode). The costly part of the projection, the reflection point on the mirror
(a root-find per point, :meth:`CatadioptricCamera.forward`), depends on the mirror and the
pinhole only, so :func:`forward_batch` solves it once for every camera's points, then applies
each camera's true intrinsics and draws each camera's noise from its own generator. The
result is, bit for bit, what each camera's :meth:`~CatadioptricCamera.forward` gives.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from radial_ibvs_gym._validation import as_float_array, check_finite, check_last_dim
from radial_ibvs_gym.camera.catadioptric import CatadioptricCamera, Projection

__all__ = [
    "forward_batch",
    "project_rows",
    "project_shared",
    "shares_reflection",
    "true_rows",
]


def shares_reflection(cameras: Sequence[CatadioptricCamera]) -> bool:
    """Whether the cameras reflect every point at the same mirror point.

    True when they share the mirror, the pinhole's height on the axis, the lens radius and
    the nominal intrinsics, and none is tilted or off the axis: they differ at most in the
    principal point, the focal ratio and the pixel noise.
    """
    if not cameras:
        return True
    key = cameras[0]._reflection_key
    # equal keys are mostly the same object (CatadioptricCamera interns them)
    return key is not None and all(
        c._reflection_key is key or c._reflection_key == key for c in cameras
    )


def forward_batch(
    cameras: Sequence[CatadioptricCamera],
    points: ArrayLike,
    rngs: Sequence[np.random.Generator | None] | None = None,
) -> Projection:
    """Project each camera's points: :meth:`CatadioptricCamera.forward`, batched.

    Parameters
    ----------
    cameras
        ``K`` cameras. Where they share the reflection (:func:`shares_reflection`) one
        root-find serves all of them; otherwise each projects its own points.
    points
        ``(K, N, 3)`` points, row ``k`` in camera ``k``'s frame, metres.
    rngs
        ``K`` generators (or ``None``) for each camera's pixel noise, drawn in the order and
        shape that camera's ``forward(points[k], rng)`` would draw it.

    Returns
    -------
    Projection
        ``pixels`` ``(K, N, 2)`` (NaN where hidden), ``mirror_points`` ``(K, N, 3)`` and
        ``visible`` ``(K, N)``: row ``k`` equal to ``cameras[k].forward(points[k], rngs[k])``.

    Raises
    ------
    ValueError
        For NaN/inf coordinates, a wrong shape, or ``K`` that differs from the number of
        cameras or generators.
    """
    p = as_float_array(points, "points")
    check_last_dim(p, 3, "points")
    check_finite(p, "points")
    k = len(cameras)
    if p.ndim != 3 or p.shape[0] != k:
        raise ValueError(f"points must have shape ({k}, N, 3) for {k} cameras, got {p.shape}")
    generators: Sequence[np.random.Generator | None] = [None] * k if rngs is None else rngs
    if len(generators) != k:
        raise ValueError(f"{len(generators)} generators for {k} cameras")
    n = p.shape[1]
    if k == 0 or not shares_reflection(cameras):
        rows = [c.forward(p[i], generators[i]) for i, c in enumerate(cameras)]
        if not rows:
            return Projection(np.zeros((0, n, 2)), np.zeros((0, n, 3)), np.zeros((0, n), bool))
        return Projection(*(np.stack(parts) for parts in zip(*rows, strict=True)))
    return project_shared(cameras, p, generators)


def project_shared(
    cameras: Sequence[CatadioptricCamera],
    p: NDArray[np.float64],
    generators: Sequence[np.random.Generator | None],
) -> Projection:
    """:func:`forward_batch` for ``K >= 1`` cameras that share the reflection, unchecked.

    The hot path of :func:`~radial_ibvs_gym.camera.measurement.camera_images`: the caller
    guarantees :func:`shares_reflection`, finite ``(K, N, 3)`` points and ``K`` generators.
    """
    n = p.shape[1]
    # each camera's noise from its own generator: rng.normal(0, std) is 0 + std * z with z
    # drawn as rng.standard_normal draws it, so one multiplication serves every camera
    stds = np.array(
        [
            c.imperfections.pixel_noise_std if rng is not None else 0.0
            for c, rng in zip(cameras, generators, strict=True)
        ]
    )
    normals = None
    if stds.any():
        quiet = np.zeros((n, 2))
        normals = np.stack(
            [
                rng.standard_normal((n, 2)) if std > 0.0 and rng is not None else quiet
                for std, rng in zip(stds.tolist(), generators, strict=True)
            ]
        )
    return project_rows(cameras[0], true_rows(cameras), p, stds, normals)


def true_rows(cameras: Sequence[CatadioptricCamera]) -> NDArray[np.float64]:
    """Each camera's true ``(fx, fy, mu_x, mu_y)``, pixels, ``(K, 4)``."""
    return np.array([c._true_row for c in cameras], dtype=np.float64).reshape(-1, 4)


def project_rows(
    first: CatadioptricCamera,
    rows: NDArray[np.float64],
    p: NDArray[np.float64],
    stds: NDArray[np.float64],
    normals: NDArray[np.float64] | None,
) -> Projection:
    """:func:`project_shared` from the cameras' numbers: their intrinsics and noise drawn.

    For a caller that keeps each camera's numbers in arrays (a vector env, over its episodes)
    and draws the noise itself (:class:`~radial_ibvs_gym.envs.noise_blocks.NoiseBlocks`).
    Unchecked, as :func:`project_shared`.

    Parameters
    ----------
    first
        One of the ``K`` cameras, which all share its reflection (:func:`shares_reflection`).
    rows
        ``(K, 4)`` each camera's true ``(fx, fy, mu_x, mu_y)``, pixels (:func:`true_rows`).
    p
        ``(K, N, 3)`` finite points, row ``k`` in camera ``k``'s frame, metres.
    stds
        ``(K,)`` each camera's pixel noise standard deviation, pixels (0: none).
    normals
        ``(K, N, 2)`` standard normal draws (zeros where a camera draws none), or ``None``
        where no camera has noise.

    Returns
    -------
    Projection
        As :func:`forward_batch`.
    """
    k, n = p.shape[:2]
    m_m, p_m = first._reflect(p.reshape(-1, 3))
    q, visible = first._sensor_rays(m_m, p_m)
    # each camera's true (fx, fy, mu_x, mu_y), applied as Intrinsics.project does
    true = rows[:, None, :]
    with np.errstate(invalid="ignore", divide="ignore"):
        x = (q[:, :2] / q[:, 2:3]).reshape(k, n, 2)
        pixels = true[..., :2] * x + true[..., 2:]
        # the sensor's size is the nominal one, shared
        visible = visible.reshape(k, n) & first.true_intrinsics.contains(pixels)
    if normals is not None:
        pixels += stds[:, None, None] * normals
    pixels = np.where(visible[..., None], pixels, np.nan)
    mirror_points = m_m - np.array([0.0, 0.0, first.camera_z])
    return Projection(pixels, mirror_points.reshape(k, n, 3), visible)
