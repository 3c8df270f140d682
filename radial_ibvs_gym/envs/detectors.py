"""The detected-points pipeline of ``measurement="detected"``, for one env or a vector env's robots.

:func:`make_detector` checks that a scenario can be rendered and labelled (one camera, a fixed
number of beacons) and builds the pipeline
(:class:`~radial_ibvs_gym.vision.pipeline.DetectedPoints`) that the scalar env holds.
:class:`DetectorRows` gives each robot of
:class:`~radial_ibvs_gym.envs.parking_vector.ParkingVectorEnv` its own pipeline (scene,
calibration, tracker), all sharing one renderer per camera (which keeps the rays' floor and
ceiling hits of up to one room height per robot), and measures a batch of robots per call:
each robot's frame is rendered and detected as the scalar env does it, with its own
generator, so the points are the same bit for bit. The frames are rendered one at a time:
shading a batch's rays in one numpy pass was measured slower per frame (its arrays leave the
cache; docs/benchmarks.md).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from radial_ibvs_gym.envs.config import ParkingConfig
from radial_ibvs_gym.vision import ImageQuality
from radial_ibvs_gym.vision.pipeline import DetectedPoints

__all__ = ["DetectorRows", "make_detector"]


def make_detector(config: ParkingConfig) -> DetectedPoints:
    """Build the detected-points pipeline of an env's arguments.

    Raises
    ------
    ValueError
        For a scenario that draws its mirror per episode (the renderer holds one camera's rays)
        or draws its landmark count (the tracker labels a fixed number of beacons).
    """
    scene = config.scenario.config
    drawn = scene.random_landmarks
    if len(scene.mirrors) > 1:
        raise ValueError(
            f"measurement='detected' renders through one camera; scenario {scene.name!r} draws "
            f"its mirror from {list(scene.mirrors)} per episode"
        )
    if drawn is not None and drawn.count_range[0] != drawn.count_range[1]:
        raise ValueError(
            f"measurement='detected' labels a fixed number of beacons; scenario {scene.name!r} "
            f"draws random_landmarks.count {list(drawn.count_range)} per episode"
        )
    return DetectedPoints(
        config.scenario.camera,
        config.scenario.goal_camera,
        scene.fixed_camera_height("measurement='detected'"),
        image_size=config.image_size,
        beacon_radius=config.beacon_radius,
        quality=ImageQuality(config.image_noise, config.image_blur, config.exposure),
    )


class DetectorRows:
    """Each of ``n`` robots' detected-points pipeline, the renderers shared.

    Parameters
    ----------
    config
        The vector env's arguments (``measurement="detected"``).
    n
        Number of robots.
    """

    def __init__(self, config: ParkingConfig, n: int) -> None:
        first = make_detector(config)
        self.rows = [first] + [first.sharing() for _ in range(n - 1)]
        for renderer in first.renderers.values():
            if renderer is not None:  # each robot's room height stays cached, as in its own
                renderer.cached_heights = n

    def __getitem__(self, i: int) -> DetectedPoints:
        return self.rows[i]

    def initial(
        self, indices: NDArray[np.intp], n_landmarks: int
    ) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
        """Return the first frames' points ``(k, L, 2)`` and masks ``(k, L)`` of envs reset."""
        return self._stack([self.rows[i].initial() for i in indices.tolist()], n_landmarks)

    def observe(
        self,
        indices: NDArray[np.intp],
        poses: NDArray[np.float64],
        rngs: list[np.random.Generator | None],
        n_landmarks: int,
    ) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
        """Render and measure the frames of the robots ``indices`` at their ``poses`` ``(N, 3)``.

        Returns the points ``(k, L, 2)`` and masks ``(k, L)``, robot ``indices[j]``'s in row
        ``j``; robot ``i``'s sensor noise is drawn from ``rngs[i]``.
        """
        found = []
        for i in indices.tolist():
            rng = rngs[i]
            assert rng is not None
            found.append(self.rows[i].observe(poses[i], rng))
        return self._stack(found, n_landmarks)

    def info(self, i: int) -> dict[str, Any]:
        """Robot ``i``'s ``info["detection"]`` (the scalar env's entry)."""
        return self.rows[i].info()

    @staticmethod
    def _stack(
        found: list[tuple[NDArray[np.float64], NDArray[np.bool_]]], n_landmarks: int
    ) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
        points = np.zeros((len(found), n_landmarks, 2))
        visible = np.zeros((len(found), n_landmarks), dtype=bool)
        for j, (p, v) in enumerate(found):
            points[j], visible[j] = p, v
        return points, visible
