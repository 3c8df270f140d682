"""``RadialIBVS/ParkingImage-v0``: the parking task seen as rendered omnidirectional images."""

from __future__ import annotations

from typing import Any

import numpy as np
from gymnasium import spaces

from radial_ibvs_gym.envs.parking import ParkingEnv
from radial_ibvs_gym.vision import ImageQuality, OmniRenderer, RoomScene
from radial_ibvs_gym.vision.pipeline import room_scene

__all__ = ["ParkingImageEnv"]

_POINT_ONLY = ("obs_mode", "privileged", "goal_depths", "measurement")


class ParkingImageEnv(ParkingEnv):
    """The parking task with the omnidirectional images as the observation (pixel-based RL).

    Same dynamics, actions, rewards, episode end, ``info`` and arguments as :class:`ParkingEnv`
    (the episode still ends "lost" when fewer than ``min_visible`` landmarks are in view). The
    observation is a ``Dict`` of two channel-last grey images, as stable-baselines3's
    ``MultiInputPolicy`` (one CNN per image) expects:

    | key | space | meaning |
    |---|---|---|
    | ``image`` | ``Box(0, 255, (S, S, 1), uint8)`` | the current omnidirectional image |
    | ``goal_image`` | ``Box(0, 255, (S, S, 1), uint8)`` | the image taken at the goal pose |

    Parameters
    ----------
    image_size
        ``S``, the side of the images, pixels (default 84, the Atari size of SB3's NatureCNN).
    beacon_radius
        Radius of the beacons, metres (default 0.25: large, so that they stay a few pixels wide
        at 84 x 84 from across the room).
    image_noise, image_blur, exposure
        Sensor noise (grey levels), blur (pixels) and exposure of both images.
    **kwargs
        :class:`ParkingEnv`'s arguments; the point-observation ones (``obs_mode``,
        ``privileged``, ``goal_depths``, ``measurement``) are refused.
    """

    _own_arguments = ("image_size", "beacon_radius", "image_noise", "image_blur", "exposure")

    def __init__(
        self,
        *args: Any,
        image_size: int = 84,
        beacon_radius: float = 0.25,
        image_noise: float = 0.0,
        image_blur: float = 0.0,
        exposure: float = 1.0,
        **kwargs: Any,
    ) -> None:
        refused = sorted(set(kwargs) & set(_POINT_ONLY))
        if refused:
            raise ValueError(f"ParkingImage-v0 observes images; it has no {refused} argument")
        super().__init__(*args, **kwargs)
        if not (isinstance(beacon_radius, (int, float)) and beacon_radius > 0):
            raise ValueError(f"beacon_radius must be positive (metres), got {beacon_radius!r}")
        self.beacon_radius = float(beacon_radius)
        self.quality = ImageQuality(image_noise, image_blur, exposure)
        height = self.scenario.config.camera_height
        self._image_renderer = OmniRenderer(self.scenario.camera, image_size, height)
        self._goal_renderer = (
            OmniRenderer(self.scenario.goal_camera, image_size, height)
            if self.scenario.goal_camera is not self.scenario.camera
            else self._image_renderer
        )
        box = spaces.Box(0, 255, (image_size, image_size, 1), np.uint8)
        self.observation_space = spaces.Dict({"image": box, "goal_image": box})  # type: ignore[assignment]
        self._scene: RoomScene | None = None
        self._goal_image: np.ndarray | None = None

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
        """Draw an episode as :meth:`ParkingEnv.reset` and render the goal image."""
        self._goal_image = None
        return super().reset(seed=seed, options=options)

    def _obs(self) -> dict[str, np.ndarray]:
        assert self.world is not None and self.episode is not None
        if self._goal_image is None:
            self._scene = room_scene(self.episode.room, self.episode.landmarks, self.beacon_radius)
            goal = self._goal_renderer.render(
                self.episode.goal, self._scene, self.quality, self.np_random
            )
            self._goal_image = goal[..., None]
        assert self._scene is not None
        image = self._image_renderer.render(
            self.world.pose, self._scene, self.quality, self.np_random
        )
        return {"image": image[..., None], "goal_image": self._goal_image.copy()}
