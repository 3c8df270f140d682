"""Image points measured from rendered images: render -> detect -> calibrate -> normalise -> match.

Used by :class:`~radial_ibvs_gym.envs.parking.ParkingEnv` with ``measurement="detected"`` (and
for the images of ``ParkingImage-v0``). The mirror border is fitted once per episode, on the
goal image (the paper calibrates once, from the mirror border's Hough circle), and reused;
when the goal image comes from another camera (mirror swap), the current camera gets its own
fit on the episode's first image. An image without a border at reset is an error.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from radial_ibvs_gym.camera import CatadioptricCamera, normalise_pixels
from radial_ibvs_gym.geometry import world_to_camera
from radial_ibvs_gym.vision import ImageQuality, OmniRenderer, RoomScene
from radial_ibvs_gym.vision.detect import BorderFit, Measurement, fit_mirror_border, measure
from radial_ibvs_gym.vision.track import BeaconTracker

__all__ = ["DetectedPoints", "room_scene"]


def room_scene(
    room: NDArray[np.float64], landmarks: NDArray[np.float64], beacon_radius: float
) -> RoomScene:
    """Build the rendered room of an episode: walls, a ceiling above every beacon, beacons."""
    height = max(2.8, float(np.max(landmarks[:, 2])) + beacon_radius + 0.3)
    return RoomScene(
        size=(float(room[0]), float(room[1])),
        height=height,
        beacons=landmarks,
        beacon_radius=beacon_radius,
    )


@dataclass
class _Frame:
    image: NDArray[np.uint8]
    measurement: Measurement


class DetectedPoints:
    """Normalised image points of the landmarks from rendered and measured images.

    Parameters
    ----------
    camera, goal_camera
        The cameras of the current and goal images.
    camera_height
        Camera height above the floor, metres.
    image_size
        Side of the rendered images, pixels.
    beacon_radius
        Radius of the beacons, metres.
    quality
        Sensor noise, blur and exposure.
    renderers
        The renderers of another pipeline of the same cameras, size and height, to share
        (:meth:`sharing`); ``None`` builds this pipeline's own.
    """

    def __init__(
        self,
        camera: CatadioptricCamera,
        goal_camera: CatadioptricCamera,
        camera_height: float,
        image_size: int = 256,
        beacon_radius: float = 0.08,
        quality: ImageQuality | None = None,
        renderers: dict[str, OmniRenderer | None] | None = None,
    ) -> None:
        if not (math.isfinite(beacon_radius) and beacon_radius > 0):
            raise ValueError(f"beacon_radius must be positive (metres), got {beacon_radius!r}")
        self.camera_height = float(camera_height)
        self.image_size = image_size
        self.renderers = renderers or {
            "current": OmniRenderer(camera, image_size, camera_height),
            "goal": OmniRenderer(goal_camera, image_size, camera_height)
            if goal_camera is not camera
            else None,
        }
        self.cameras = {"current": camera, "goal": goal_camera}
        self.beacon_radius = float(beacon_radius)
        self.quality = quality or ImageQuality()
        self.scene: RoomScene | None = None
        self.border: BorderFit | None = None
        self.tracker: BeaconTracker | None = None
        self.status = "ok"
        self.last: dict[str, _Frame] = {}

    def sharing(self) -> DetectedPoints:
        """Return a pipeline of its own episode state that shares this one's renderers.

        A renderer holds every pixel's ray (computed once per camera, megabytes at 384 px):
        the robots of a vector env share them, each with its own scene, calibration and
        tracker.
        """
        return DetectedPoints(
            self.cameras["current"],
            self.cameras["goal"],
            self.camera_height,
            self.image_size,
            self.beacon_radius,
            self.quality,
            renderers=self.renderers,
        )

    def _renderer(self, which: str) -> OmniRenderer:
        return self.renderers[which] or self.renderers["current"]  # type: ignore[return-value]

    def predicted(
        self,
        pose: NDArray[np.float64],
        which: str,
        landmarks: NDArray[np.float64] | None = None,
    ) -> NDArray[np.float64]:
        """Image positions ``(N, 2)`` (pixels) of the landmarks seen from ``pose``.

        The forward projection through the camera ``which`` (``"current"`` or ``"goal"``) of
        ``landmarks`` ``(N, 3)`` (metres; default: the scene's beacons); NaN where hidden.
        What labels the landmarks at an episode's start.
        """
        if landmarks is None:
            assert self.scene is not None
            landmarks = self.scene.beacons
        p_cam = world_to_camera(landmarks, pose, self.camera_height)
        proj = self.cameras[which].forward(p_cam)
        return self._renderer(which).sensor_to_image(proj.pixels)

    def _points(
        self, match: NDArray[np.int64], result: Measurement
    ) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
        n = len(match)
        points = np.zeros((n, 2))
        visible = match >= 0
        if visible.any():
            points[visible] = result.x_n[match[visible]]
        return points, visible

    def reset(
        self,
        room: NDArray[np.float64],
        landmarks: NDArray[np.float64],
        start: NDArray[np.float64],
        goal: NDArray[np.float64],
        rng: np.random.Generator,
    ) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
        """Start an episode: render the goal image and the first image, then :meth:`start`.

        Returns
        -------
        goal_points, goal_visible
            ``(N, 2)`` goal image points (zeros where not detected) and ``(N,)`` mask.

        Raises
        ------
        ValueError
            When the goal image (or the first current image, from another camera) shows no
            mirror border: nothing can be calibrated.
        """
        self.scene = room_scene(room, landmarks, self.beacon_radius)
        goal_image = self._renderer("goal").render(goal, self.scene, self.quality, rng)
        first_image = self._renderer("current").render(start, self.scene, self.quality, rng)
        return self.start(
            goal_image,
            self.predicted(goal, "goal"),
            first_image,
            self.predicted(start, "current"),
        )

    def start(
        self,
        goal_image: NDArray[np.uint8],
        goal_labels: NDArray[np.float64],
        first_image: NDArray[np.uint8],
        first_labels: NDArray[np.float64],
    ) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
        """Start an episode from its images: calibrate, measure and label the goal and first.

        The mirror border is fitted on the goal image (the paper calibrates once); a goal
        camera other than the current one (mirror swap) fits its own on the first image.
        Each image's beacons are labelled by the nearest of the given positions.

        Parameters
        ----------
        goal_image, first_image
            ``(H, W)`` uint8 grey levels: the goal image and the episode's first image.
        goal_labels, first_labels
            ``(N, 2)`` where each landmark is expected in each image, pixels (NaN: not
            expected): :meth:`predicted` from a map and the poses, or a user's labels.

        Returns
        -------
        goal_points, goal_visible
            ``(N, 2)`` goal image points (zeros where not detected) and ``(N,)`` mask.

        Raises
        ------
        ValueError
            When an image to calibrate on shows no mirror border.
        """
        goal_border = self._calibrate(goal_image, "goal image")
        result = measure(goal_image, border=goal_border)
        self.last["goal"] = _Frame(goal_image, result)
        n = len(goal_labels)
        self.tracker = BeaconTracker(n, gate_px=self._gate())
        goal_match = self.tracker.start(result.centres, goal_labels, goal_border.centre)
        goal_points, goal_visible = self._points(goal_match, result)
        reference = np.full((n, 2), np.nan)  # the goal image's positions: the cyclic order
        reference[goal_visible] = result.centres[goal_match[goal_visible]]
        # one calibration per camera: the goal camera's border, unless the current one differs
        self.border = (
            goal_border
            if self.renderers["goal"] is None
            else self._calibrate(first_image, "first current image")
        )
        first = measure(first_image, border=self.border)
        self.last["current"] = _Frame(first_image, first)
        match = self.tracker.start(first.centres, first_labels, self._centre(), reference)
        self._current = self._points(match, first)
        self.status = first.status
        return goal_points, goal_visible

    def _calibrate(self, image: NDArray[np.uint8], what: str) -> BorderFit:
        border = fit_mirror_border(image)
        if border is None:
            raise ValueError(
                f"the mirror border was not found in the {what} (a black, blank or saturated "
                f"frame: exposure={self.quality.exposure!r}), so there is no calibration"
            )
        return border

    def _gate(self) -> float:
        return 0.04 * self._renderer("current").size

    def _centre(self) -> NDArray[np.float64]:
        if self.border is not None:
            return self.border.centre
        r = self._renderer("current")
        return r.sensor_to_image(r.camera.intrinsics.principal_point)

    def initial(self) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
        """Return the first current frame's points and mask (after :meth:`reset`)."""
        return self._current

    def observe(
        self, pose: NDArray[np.float64], rng: np.random.Generator
    ) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
        """Render the current image at ``pose`` and :meth:`observe_image` it."""
        assert self.scene is not None
        image = self._renderer("current").render(pose, self.scene, self.quality, rng)
        return self.observe_image(image)

    def observe_image(
        self, image: NDArray[np.uint8] | None
    ) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
        """Measure a current image and match it with the landmarks (after :meth:`start`).

        Parameters
        ----------
        image
            ``(H, W)`` uint8 grey levels; ``None``: a dropped frame, nothing detected (every
            tracked landmark coasts, as after a frame without beacons).

        Returns
        -------
        points, visible
            ``(N, 2)`` eq. (7) points (zeros where not tracked) and ``(N,)`` mask. A landmark
            coasting after a missed frame keeps its predicted position (its last ``x_n``).
        """
        assert self.tracker is not None
        if image is None:
            result = Measurement("no_frame", np.zeros((0, 2)), np.zeros((0, 2)), self.border, {})
        else:
            result = measure(image, border=self.border)
            self.last["current"] = _Frame(image, result)
        match = self.tracker.update(result.centres, self._centre())
        points, visible = self._points(match, result)
        coasting = self.tracker.tracked & ~visible
        if coasting.any() and self.border is not None:
            ratio = self.border.rho_f
            points[coasting] = normalise_pixels(
                self.tracker.position[coasting], self.border.centre, ratio
            )
            visible = visible | coasting
        self.status = result.status
        return points, visible

    def info(self) -> dict[str, Any]:
        """Return the ``info["detection"]`` entry: status, counts and the calibration found."""
        frame = self.last.get("current")
        tracked = self.tracker.tracked if self.tracker is not None else np.zeros(0, bool)
        return {
            "status": self.status,
            "n_detected": 0 if frame is None else len(frame.measurement.centres),
            "n_tracked": int(tracked.sum()),
            "principal_point_px": None if self.border is None else self.border.centre.copy(),
            "rho_f": None if self.border is None else self.border.rho_f,
            "rejected": {} if frame is None else dict(frame.measurement.rejected),
        }
