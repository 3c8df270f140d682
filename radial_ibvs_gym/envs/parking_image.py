"""``RadialIBVS/ParkingImage-v0``: the parking task seen as rendered omnidirectional images."""

from __future__ import annotations

from typing import Any

import numpy as np
from gymnasium import spaces

from radial_ibvs_gym.envs.parking import ParkingEnv
from radial_ibvs_gym.vision import ImageQuality, OmniRenderer, RoomScene
from radial_ibvs_gym.vision.pipeline import room_scene

__all__ = ["IMAGE_LAYOUTS", "ParkingImageEnv"]

#: the observation layouts of ``ParkingImage-v0`` (``image_layout``)
IMAGE_LAYOUTS = ("dict", "channels")

_POINT_ONLY = ("obs_mode", "privileged", "goal_depths", "measurement")


class ParkingImageEnv(ParkingEnv):
    """The parking task with the omnidirectional images as the observation (pixel-based RL).

    Same dynamics, actions, rewards, episode end, ``info`` and arguments as :class:`ParkingEnv`
    (the episode still ends "lost" when fewer than ``min_visible`` landmarks are in view). The
    observation is two channel-last grey images, in one of two layouts (``image_layout``):

    - ``"dict"`` (default): ``Dict(image=Box(0, 255, (S, S, 1), uint8), goal_image=...)``,
      for SB3's ``MultiInputPolicy`` (one CNN per image);
    - ``"channels"``: ``Box(0, 255, (S, S, 2), uint8)``, channel 0 the current image and
      channel 1 the goal image, for SB3's ``CnnPolicy``, Gymnasium's image wrappers
      (``ResizeObservation``, ``FrameStackObservation``) and libraries that take a ``Box``.

    ``image`` is the current omnidirectional image, ``goal_image`` the image taken at the goal
    pose.

    Parameters
    ----------
    image_size
        ``S``, the side of the images, pixels (default 84, the Atari size of SB3's NatureCNN).
    beacon_radius
        Radius of the beacons, metres (default 0.25: large, so that they stay a few pixels wide
        at 84 x 84 from across the room).
    image_noise, image_blur, exposure
        Sensor noise (grey levels), blur (pixels) and exposure of both images.
    image_layout
        ``"dict"`` or ``"channels"`` (the list above).
    **kwargs
        :class:`ParkingEnv`'s arguments; the point-observation ones (``obs_mode``,
        ``privileged``, ``goal_depths``, ``measurement``) are refused.
    """

    _own_arguments = (
        "image_size",
        "beacon_radius",
        "image_noise",
        "image_blur",
        "exposure",
        "image_layout",
    )

    def __init__(
        self,
        *args: Any,
        image_size: int = 84,
        beacon_radius: float = 0.25,
        image_noise: float = 0.0,
        image_blur: float = 0.0,
        exposure: float = 1.0,
        image_layout: str = "dict",
        **kwargs: Any,
    ) -> None:
        if image_layout not in IMAGE_LAYOUTS:
            raise ValueError(f"unknown image_layout {image_layout!r}; valid: {list(IMAGE_LAYOUTS)}")
        refused = sorted(set(kwargs) & set(_POINT_ONLY))
        if refused:
            raise ValueError(f"ParkingImage-v0 observes images; it has no {refused} argument")
        super().__init__(*args, **kwargs)
        if not (isinstance(beacon_radius, (int, float)) and beacon_radius > 0):
            raise ValueError(f"beacon_radius must be positive (metres), got {beacon_radius!r}")
        self.beacon_radius = float(beacon_radius)
        self.quality = ImageQuality(image_noise, image_blur, exposure)
        height = self.scenario.config.fixed_camera_height("ParkingImage-v0's renderer")
        if len(self.scenario.config.mirrors) > 1:
            raise ValueError(
                f"ParkingImage-v0 renders through one camera; scenario "
                f"{self.scenario.config.name!r} draws its mirror from "
                f"{list(self.scenario.config.mirrors)} per episode"
            )
        self._image_renderer = OmniRenderer(self.scenario.camera, image_size, height)
        self._goal_renderer = (
            OmniRenderer(self.scenario.goal_camera, image_size, height)
            if self.scenario.goal_camera is not self.scenario.camera
            else self._image_renderer
        )
        self.image_layout = image_layout
        if image_layout == "channels":
            both = spaces.Box(0, 255, (image_size, image_size, 2), np.uint8)
            self.observation_space = both  # type: ignore[assignment]
        else:
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

    def _obs(self) -> Any:
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
        if self.image_layout == "channels":
            return np.concatenate([image[..., None], self._goal_image], axis=-1)
        return {"image": image[..., None], "goal_image": self._goal_image.copy()}
