"""The omnidirectional image a catadioptric camera sees in a box room with black wall beacons.

Each pixel's reflected ray is fixed in the camera frame (backward projection through the exact
mirror, central or not, with the camera's true intrinsics and imperfections), so it is computed
once per camera; a frame then costs only the ray-room intersections: rotate and shift the rays
by the robot's pose, intersect them with the walls, floor and ceiling, shade, and paint the
beacons (discs on the walls). Pure numpy.

A ray that meets the floor or the ceiling meets it at a point fixed in the camera frame (the
floor and ceiling do not turn with the robot), so its shade is computed once per room height,
and, for a frame without blur or noise, its quantised grey level too. A frame leaves out the
rays whose floor or ceiling hit lies nearer the camera's axis than any wall (they meet no wall
first: the room is convex and the ray starts inside it), intersects only the others with the
walls, and tests each beacon only against the rays that meet its wall within an azimuth
window about its bearing (:mod:`radial_ibvs_gym.vision.room_rays`). The image is
the same, bit for bit, as intersecting every ray with every surface (``tests/vision/test_pixels.py``
checks it against that reference).
"""

from __future__ import annotations

import math
from collections import OrderedDict
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from radial_ibvs_gym._validation import as_float_array, check_finite, check_last_dim
from radial_ibvs_gym.camera import CatadioptricCamera
from radial_ibvs_gym.limits import MAX_IMAGE_BLUR, MAX_IMAGE_NOISE, MAX_IMAGE_SIZE
from radial_ibvs_gym.vision.room_rays import SHADE, VerticalHits, shade_rays
from radial_ibvs_gym.vision.room_scene import RoomScene

__all__ = ["ImageQuality", "OmniRenderer", "RoomScene"]

#: grey levels (0..1) outside the mirror's image and in its blind centre
_OUTSIDE, _BLIND = 0.04, 0.3


@dataclass(frozen=True)
class ImageQuality:
    """Image imperfections of a rendered frame.

    Attributes
    ----------
    noise_std
        Standard deviation of additive Gaussian sensor noise, grey levels (0-255).
    blur_sigma
        Gaussian blur, pixels of the rendered image (0: none).
    exposure
        Multiplies the brightness (1: nominal).
    """

    noise_std: float = 0.0
    blur_sigma: float = 0.0
    exposure: float = 1.0

    def __post_init__(self) -> None:
        for name, top in (("noise_std", MAX_IMAGE_NOISE), ("blur_sigma", MAX_IMAGE_BLUR)):
            value = getattr(self, name)
            if not (math.isfinite(value) and 0 <= value <= top):
                raise ValueError(f"{name} must be in [0, {top:g}] (limits), got {value!r}")
        if not (math.isfinite(self.exposure) and self.exposure > 0):
            raise ValueError(f"exposure must be positive, got {self.exposure!r}")


class OmniRenderer:
    """Render a camera's omnidirectional view of a :class:`RoomScene`.

    The rendered image is a ``size x size`` crop of the sensor centred on the nominal principal
    point and just covering the image of the mirror rim, resampled: rendered pixel ``(row i,
    column j)`` is the sensor point ``(u, v) = origin + scale * (j + 0.5, i + 0.5)``.

    Parameters
    ----------
    camera
        The camera (its true intrinsics and imperfections shape the image).
    size
        Side of the rendered image, pixels.
    camera_height
        Height of the camera above the floor, metres.
    """

    def __init__(self, camera: CatadioptricCamera, size: int = 256, camera_height: float = 1.8):
        if not (isinstance(size, int) and 16 <= size <= MAX_IMAGE_SIZE):
            raise ValueError(f"size must be an integer in 16..{MAX_IMAGE_SIZE}, got {size!r}")
        if not (math.isfinite(camera_height) and camera_height > 0):
            raise ValueError(f"camera_height must be positive, got {camera_height!r}")
        self.camera, self.size, self.camera_height = camera, size, float(camera_height)
        k = camera.intrinsics
        r_rim = camera.visible_radius
        depth = float(camera.mirror.profile_z(r_rim)) - camera.camera_z
        rim_px = 1.04 * max(k.fx, k.fy) * r_rim / abs(depth)
        self.scale = 2.0 * rim_px / size  # sensor pixels per rendered pixel
        self.origin = np.array(k.principal_point) - rim_px  # sensor (u, v) of the corner
        jj, ii = np.meshgrid(np.arange(size) + 0.5, np.arange(size) + 0.5)
        sensor = self.origin + self.scale * np.stack([jj, ii], axis=-1)
        origins, directions = camera.backward(sensor)
        seen = np.isfinite(directions).all(axis=-1)
        blind = seen & (np.hypot(origins[..., 0], origins[..., 1]) < camera.blind_radius)
        self._background = np.full((size, size), _OUTSIDE)
        self._background[blind] = _BLIND
        rays = seen & ~blind
        self._index = np.flatnonzero(rays)
        self._origins = origins[rays]
        self._directions = directions[rays]
        self._flat_shade = np.where(self._directions[:, 2] > 0, SHADE["ceiling"], SHADE["floor"])
        #: how many room heights' ray hits (and quantised images) are kept, the latest used;
        #: robots of a vector env that share this renderer keep one each at most
        self.cached_heights = 1
        self._vertical_cache: OrderedDict[float, VerticalHits] = OrderedDict()
        # (room height, exposure): the quantised image of v.image at them
        self._quantised_cache: OrderedDict[tuple[float, float], NDArray[np.uint8]] = OrderedDict()

    def _vertical(self, height: float) -> VerticalHits:
        """Return the rays' floor or ceiling hits for a room height, sorted by reach (cached)."""
        hits = _cached(self._vertical_cache, height)
        if hits is None:
            hits = VerticalHits.of(
                self._origins,
                self._directions,
                self._index,
                self._flat_shade,
                self._background,
                self.camera_height,
                height,
            )
            _store(self._vertical_cache, height, hits, self.cached_heights)
        return hits

    def sensor_to_image(self, uv: ArrayLike) -> NDArray[np.float64]:
        """Sensor pixels ``(..., 2)`` to rendered-image pixels ``(..., 2)`` (column, row)."""
        return (np.asarray(uv, dtype=np.float64) - self.origin) / self.scale - 0.5

    def image_to_sensor(self, xy: ArrayLike) -> NDArray[np.float64]:
        """Rendered-image pixels ``(..., 2)`` (column, row) to sensor pixels ``(..., 2)``."""
        return self.origin + self.scale * (np.asarray(xy, dtype=np.float64) + 0.5)

    def render(
        self,
        pose: ArrayLike,
        scene: RoomScene,
        quality: ImageQuality | None = None,
        rng: np.random.Generator | None = None,
    ) -> NDArray[np.uint8]:
        """Render the view from a robot pose.

        Parameters
        ----------
        pose
            ``(3,)`` robot pose ``(x, y, yaw)``, metres and radians.
        scene
            The room.
        quality
            Blur, exposure and sensor noise (default: a perfect image).
        rng
            Generator of the sensor noise (needed when ``quality.noise_std > 0``).

        Returns
        -------
        numpy.ndarray
            ``(size, size)`` uint8 grey image.
        """
        quality = quality or ImageQuality()
        if quality.blur_sigma > 0 or quality.noise_std > 0:  # they mix or draw every pixel
            return _finish(self.shade(pose, scene), quality, rng)
        # exposure and quantising act pixel by pixel: the rays that keep their floor or
        # ceiling shade keep their quantised grey level too (cached per room height)
        v, k, x, y, c, s = self._frame(pose, scene)
        key = (scene.height, quality.exposure)
        base = _cached(self._quantised_cache, key)
        if base is None:
            base = _quantise(v.image, quality.exposure)
            _store(self._quantised_cache, key, base, self.cached_heights)
        image = base.copy()
        image[v.index[k:]] = _quantise(shade_rays(v, k, x, y, c, s, scene), quality.exposure)
        return image.reshape(self.size, self.size)

    def shade(self, pose: ArrayLike, scene: RoomScene) -> NDArray[np.float64]:
        """Compute the perfect image's grey levels from a pose, before exposure and quantising.

        Parameters
        ----------
        pose
            ``(3,)`` robot pose ``(x, y, yaw)``, metres and radians.
        scene
            The room.

        Returns
        -------
        numpy.ndarray
            ``(size, size)`` grey levels in ``[0, 1]``.
        """
        v, k, x, y, c, s = self._frame(pose, scene)
        image = v.image.copy()
        image[v.index[k:]] = shade_rays(v, k, x, y, c, s, scene)
        return image.reshape(self.size, self.size)

    def _frame(
        self, pose: ArrayLike, scene: RoomScene
    ) -> tuple[VerticalHits, int, float, float, float, float]:
        """Return the rays of the room's height, the first that may meet a wall, the pose.

        The rays whose floor or ceiling hit is nearer the camera's axis than any wall meet no
        wall first, whatever the heading (the room is convex and the rays start in it): they
        keep the floor or ceiling shade of ``v.image``. Returns ``(v, k, x, y, cos yaw, sin
        yaw)``: the rays from the ``k``-th on are the others.
        """
        p = as_float_array(pose, "pose")
        check_last_dim(p, 3, "pose")
        check_finite(p, "pose")
        x, y, yaw = (float(v) for v in p)
        v = self._vertical(scene.height)
        w, depth = scene.size
        inner = min(x, w - x, y, depth - y) - _MARGIN
        k = int(np.searchsorted(v.reach, inner)) if inner > v.origin_reach else 0
        return v, k, x, y, math.cos(yaw), math.sin(yaw)


def _cached(cache: OrderedDict[Any, Any], key: Any) -> Any:
    """Return ``cache[key]`` (now the latest used) or None."""
    value = cache.get(key)
    if value is not None:
        cache.move_to_end(key)
    return value


def _store(cache: OrderedDict[Any, Any], key: Any, value: Any, size: int) -> None:
    """Keep ``value`` under ``key``, dropping the least recently used beyond ``size`` entries."""
    cache[key] = value
    while len(cache) > max(1, size):
        cache.popitem(last=False)


#: metres: a floor hit this much nearer than the walls is on the floor, in every rounding
_MARGIN = 1e-6


def _finish(
    image: NDArray[np.float64], quality: ImageQuality, rng: np.random.Generator | None
) -> NDArray[np.uint8]:
    """Apply blur, exposure and noise; quantise to uint8."""
    out = 255.0 * quality.exposure * image
    if quality.blur_sigma > 0:
        import cv2

        out = np.asarray(cv2.GaussianBlur(out, (0, 0), quality.blur_sigma), dtype=np.float64)
    if quality.noise_std > 0:
        if rng is None:
            raise ValueError("sensor noise needs a random generator (rng)")
        out = out + rng.normal(0.0, quality.noise_std, out.shape)
    return _to_uint8(out)


def _quantise(image: NDArray[np.float64], exposure: float) -> NDArray[np.uint8]:
    """:func:`_finish` without blur and noise: pixel by pixel, so it may quantise any pixels."""
    return _to_uint8(255.0 * exposure * image)


def _to_uint8(out: NDArray[np.float64]) -> NDArray[np.uint8]:
    """Round grey levels (0-255) to the nearest integer, clip and convert (``out`` is reused)."""
    np.rint(out, out=out)
    np.clip(out, 0, 255, out=out)
    return out.astype(np.uint8)
