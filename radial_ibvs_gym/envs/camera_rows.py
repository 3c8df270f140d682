"""A vector env's imperfect cameras as arrays, measured together at each step.

Each robot of :class:`~radial_ibvs_gym.envs.parking_vector.ParkingVectorEnv` has its own
camera (its principal point, focal ratio and noise drawn per episode). :class:`CameraRows`
holds what the batched projection reads of them, updated once per episode rather than read
camera by camera at each step: their true intrinsics ``(N, 4)``, their noise levels ``(N,)``,
whether they all share one reflection, and their noise drawn ahead
(:class:`~radial_ibvs_gym.envs.noise_blocks.NoiseBlocks`). :meth:`CameraRows.measure` gives,
bit for bit, :func:`~radial_ibvs_gym.camera.measurement.camera_images` of the same cameras
and generators.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from radial_ibvs_gym.camera import measurement
from radial_ibvs_gym.camera.catadioptric import CatadioptricCamera
from radial_ibvs_gym.envs.noise_blocks import NoiseBlocks

__all__ = ["CameraRows"]


class _Alone:
    """The reflection key of a camera measured alone: equal to no other env's."""

    __slots__ = ()


class CameraRows:
    """The current camera of each of ``n`` envs, as arrays.

    Parameters
    ----------
    n
        Number of envs.
    landmarks
        Landmark slots of one image, ``L``.
    block
        Steps of noise drawn per generator call (:class:`NoiseBlocks`; ``None``: its default).
    """

    def __init__(self, n: int, landmarks: int, block: int | None = None) -> None:
        self.cameras: list[CatadioptricCamera | None] = [None] * n
        self.rows = np.zeros((n, 4))
        self.stds = np.zeros(n)
        self._keys: list[Any] = [_Alone() for _ in range(n)]
        self._count: Counter[Any] = Counter(self._keys)
        self.noise = NoiseBlocks(n, landmarks, block)

    def put(self, i: int, camera: CatadioptricCamera) -> None:
        """Make ``camera`` env ``i``'s (at its reset)."""
        self.cameras[i] = camera
        self.rows[i] = camera._true_row
        self.stds[i] = camera.imperfections.pixel_noise_std
        key: Any = camera._reflection_key if camera.imperfections.any else None
        if key is None:  # measured alone: tilted, off the axis or without imperfections
            key = _Alone()
        self._count[self._keys[i]] -= 1
        if not self._count[self._keys[i]]:
            del self._count[self._keys[i]]
        self._keys[i] = key
        self._count[key] += 1

    @property
    def shared(self) -> bool:
        """Whether every env's camera has imperfections and they share one reflection."""
        return len(self._count) == 1 and not isinstance(next(iter(self._count)), _Alone)

    def measure(
        self,
        indices: NDArray[np.intp],
        p_cam: NDArray[np.float64],
        rngs: Sequence[np.random.Generator | None],
    ) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
        """Normalised image points of the envs ``indices`` through their cameras.

        Parameters
        ----------
        indices
            ``(k,)`` the envs.
        p_cam
            ``(k, L, 3)`` their landmarks, each in its camera's frame, metres.
        rngs
            Every env's generator, by env (the pixel noise of ``rngs[i]`` for env ``i``).

        Returns
        -------
        points, visible
            ``(k, L, 2)`` (zeros where hidden) and ``(k, L)``, as
            :func:`~radial_ibvs_gym.camera.measurement.camera_images` gives them.
        """
        if not self.shared:  # camera by camera where they differ: the generators read directly
            rows = indices.tolist()
            for i in rows:
                self.noise.sync(i, rngs[i])
            cameras = [c for i in rows if (c := self.cameras[i]) is not None]
            return measurement.camera_images(cameras, p_cam, [rngs[i] for i in rows])
        first = self.cameras[int(indices[0])] if len(indices) else None
        if first is None:
            return np.zeros((*p_cam.shape[:2], 2)), np.zeros(p_cam.shape[:2], dtype=bool)
        stds = self.stds[indices]
        normals = None
        noisy = stds > 0.0
        if noisy.all():
            normals = self.noise.draw(indices, rngs)
        elif noisy.any():
            normals = np.zeros((len(indices), p_cam.shape[1], 2))
            normals[noisy] = self.noise.draw(indices[noisy], rngs)
        return measurement.camera_images_shared(first, self.rows[indices], p_cam, stds, normals)
