"""Drawing a parking episode and taking its goal image (the scalar and the vector envs alike).

:class:`EpisodeSource` draws an episode from the scenario with the env's generator (room,
landmarks, start, goal, the camera's imperfections where the scenario gives ranges), takes the
goal image, and keeps what the env needs of it in an :class:`EpisodeSetup`. The scalar env
(:class:`~radial_ibvs_gym.envs.parking.ParkingEnv`) and the native vector env
(:class:`~radial_ibvs_gym.envs.parking_vector.ParkingVectorEnv`, one draw per robot) share it,
so a seed gives the same episode in both.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from radial_ibvs_gym.camera import Imperfections
from radial_ibvs_gym.camera.measurement import camera_image, camera_images
from radial_ibvs_gym.envs.config import ParkingConfig
from radial_ibvs_gym.envs.feature_errors import unit_or_dummy
from radial_ibvs_gym.envs.missed import MissedState
from radial_ibvs_gym.envs.observation import radial_image
from radial_ibvs_gym.features import c_ij
from radial_ibvs_gym.geometry import world_to_camera, wrap_angle_scalar
from radial_ibvs_gym.geometry.bearing_pose import solve_goal_pose
from radial_ibvs_gym.physics.base import footprint_collides, start_pose_error
from radial_ibvs_gym.scenarios import Episode
from radial_ibvs_gym.scenarios.spec import MirrorName
from radial_ibvs_gym.vision.pipeline import DetectedPoints

__all__ = ["EpisodeSetup", "EpisodeSource"]


@dataclass
class EpisodeSetup:
    """What an env keeps of a drawn episode (the scalar and the vector envs alike).

    Attributes
    ----------
    episode
        The drawn episode (room, landmarks, start, goal; the goal's yaw wrapped).
    goal_depths
        ``(N,)`` goal depths ``d*`` given to the policy, metres (times ``depth_scale``).
    landmarks_c
        ``(N,)`` the landmarks on the floor plane as complex numbers ``x + i y``, metres.
    radius_bounds
        Per camera (``"current"``, ``"goal"``): the interval of horizontal distances the mirror
        sees at each landmark's height, ``(lo, hi)`` each ``(N,)``; ``None`` for a camera with
        imperfections (projected exactly instead).
    goal_points, goal_visible
        ``(N, 2)`` the goal image (zeros where hidden) and ``(N,)`` its visibility.
    c_goal
        ``(M,)`` the goal image's ``c*_ij`` (``obs_mode="features"``; else ``None``).
    cameras
        The episode's cameras, ``"current"`` and ``"goal"``: the scenario's, or built with
        the imperfections drawn for this episode.
    imperfections
        The imperfections drawn for this episode (``None``: the scenario draws none).
    map
        The privileged map of the episode (:meth:`EpisodeSource.map_observation`), computed
        once at reset when ``privileged_map=True``; else ``None``.
    missed
        The episode's missed detections (``missed_detections``), or ``None``.
    image_goal
        ``(3,)`` the *image goal* (``privileged_goal="image"``): the pose whose noise-free
        image through the episode's camera matches the goal image
        (:meth:`EpisodeSource.image_goal`); else ``None``.
    landmarks
        ``(N, 3)`` the landmarks the env observes, metres: the episode's, then (a scenario
        that draws its landmark count) copies of the first that are never visible, up to the
        scenario's most. ``None``: the episode's own.
    present
        ``(N,)`` which of ``landmarks`` the episode has (``None``: all).
    goal_frames
        The noisy frames the goal image averaged (``goal_image_frames > 1``): their points
        ``(F, N, 2)`` (zeros where hidden) and visibility ``(F, N)``; else ``None``.
    """

    episode: Episode
    goal_depths: np.ndarray
    landmarks_c: np.ndarray
    radius_bounds: dict[str, tuple[np.ndarray, np.ndarray] | None]
    goal_points: np.ndarray
    goal_visible: np.ndarray
    c_goal: np.ndarray | None = None
    cameras: dict[str, Any] = field(default_factory=dict)
    imperfections: Imperfections | None = None
    map: dict[str, np.ndarray] | None = None
    slot_order: np.ndarray | None = None
    missed: MissedState | None = None
    image_goal: np.ndarray | None = None
    landmarks: np.ndarray | None = None
    present: np.ndarray | None = None
    goal_frames: tuple[np.ndarray, np.ndarray] | None = None

    @property
    def points_w(self) -> np.ndarray:
        """``(N, 3)`` the landmarks the env observes (:attr:`landmarks`), metres."""
        return self.episode.landmarks if self.landmarks is None else self.landmarks

    @property
    def privileged_goal(self) -> np.ndarray:
        """The goal pose the privileged observation shows: the image goal, else the true goal."""
        return self.episode.goal if self.image_goal is None else self.image_goal


class EpisodeSource:
    """Draws the episodes of one env (or of every robot of a vector env) from its config.

    Parameters
    ----------
    config
        The env's arguments.
    detector
        The detected-points pipeline of a scalar env with ``measurement="detected"`` (it takes
        the goal image from pixels), or ``None``.
    """

    def __init__(self, config: ParkingConfig, detector: DetectedPoints | None = None) -> None:
        self.config = config
        self._detector = detector
        self._start_reach = config.start_reach
        self._bounds_cache: dict[str, tuple[np.ndarray, np.ndarray]] = {}
        self._nominal: dict[MirrorName | None, Any] = {}  # the map's cameras, by mirror

    @property
    def start_reach(self) -> float:
        """The fraction of the start distribution drawn from, in ``(0, 1]`` (a curriculum).

        At ``1`` the scenario draws starts as it says. Below, each start lies within
        ``start_reach`` times the scenario's start-goal distance bounds of its goal, with a
        heading within ``start_reach * pi`` radians of the goal's
        (:meth:`radial_ibvs_gym.scenarios.Scenario.sample`). Setting it takes effect at the
        next draw: a reverse curriculum raises it from near 0 to 1 over training. Only for
        scenarios whose starts are ``anywhere`` (``random``, ``random-obstacles``).
        """
        return self._start_reach

    @start_reach.setter
    def start_reach(self, value: float) -> None:
        self._start_reach = self.config.scenario.check_reach(
            value, self.config.tasks, "start_reach"
        )

    def setup_episode(
        self,
        rng: np.random.Generator,
        task: int | None,
        options: dict[str, Any],
        detector: DetectedPoints | None = None,
    ) -> EpisodeSetup:
        """Draw an episode with ``rng`` and take its goal image (the vector env uses it too).

        Parameters
        ----------
        rng
            The env's generator.
        task
            Task index, or ``None`` to draw one.
        options
            Reset options: ``start`` and ``goal`` poses fix those of the episode.
        detector
            The robot's detected-points pipeline (a vector env's robot), else the source's own.

        Raises
        ------
        ValueError
            For a bad option, or a goal image with fewer than ``min_visible`` landmarks
            (detected points: in 10 draws).
        """
        detector = detector if detector is not None else self._detector
        # detected points: a goal image can show fewer beacons than the scenario guaranteed
        # (too small, cut by the rim); draw again, a bounded number of times
        attempts = 10 if detector is not None and "goal" not in options else 1
        for attempt in range(attempts):
            episode = self._draw_episode(rng, task, options)
            cameras, drawn = self._episode_cameras(rng, episode.mirror)
            landmarks, present = self._observed(episode.landmarks)
            heights = landmarks[:, 2] - episode.camera_height
            bounds: dict[str, tuple[np.ndarray, np.ndarray] | None] = {}
            for which, camera in cameras.items():
                bounds[which] = self._radius_bounds(which, camera, heights, present)
            depths = self.config.scenario.goal_depths(episode)
            setup = EpisodeSetup(
                episode=episode,
                goal_depths=np.pad(depths, (0, len(landmarks) - len(depths))),
                landmarks_c=landmarks[:, 0] + 1j * landmarks[:, 1],
                radius_bounds=bounds,
                goal_points=np.zeros((len(landmarks), 2)),
                goal_visible=np.zeros(len(landmarks), dtype=bool),
                cameras=cameras,
                imperfections=drawn,
                landmarks=None if present is None else landmarks,
                present=present,
            )
            if detector is not None:
                setup.goal_points, setup.goal_visible = detector.reset(
                    episode.room, episode.landmarks, episode.start, episode.goal, rng
                )
            else:
                setup.goal_points, setup.goal_visible = self.image(setup, episode.goal, "goal", rng)
            if setup.goal_visible.sum() >= self.config.min_visible:
                break
            if attempt == attempts - 1:
                seen = "detected" if detector is not None else "visible"
                raise ValueError(
                    f"only {int(setup.goal_visible.sum())} landmarks are {seen} at the goal "
                    f"{episode.goal.tolist()}; at least {self.config.min_visible} are needed"
                    + (f" (in {attempts} draws)" if attempts > 1 else "")
                )
        if self.config.obs_mode == "features":
            setup.c_goal = c_ij(unit_or_dummy(setup.goal_points, setup.goal_visible))
        if self.config.privileged_map:  # fixed for the episode: computed once, copied at each step
            setup.map = self.map_observation(setup.episode)
        if self.config.privileged_goal == "image":  # noise-free images: no draw from rng
            setup.image_goal = self.image_goal(setup)
        if self.config.missed_detections is not None:
            setup.missed = self.config.missed_detections.start(rng, len(setup.points_w))
        if self.config.slot_order == "random":  # the last draw: the episode is the same as fixed's
            assert self.config.slots is not None
            setup.slot_order = self.config.slots.draw_order(rng)
        return setup

    def image_goal(self, setup: EpisodeSetup, iterations: int = 20) -> np.ndarray:
        """Return the pose ``(x, y, yaw)`` that the episode's goal image shows (metres, radians).

        An image-based policy knows the goal only through the goal image; through a noisy camera
        that image is a noisy draw, and the pose it shows is not quite the goal. This is the
        pose whose noise-free image through the episode's current camera matches the goal
        image: from the true goal, the goal's pose relative to the noise-free image is solved
        from the bearings and the goal depths
        (:func:`radial_ibvs_gym.geometry.bearing_pose.solve_goal_pose`), the pose moves there,
        and so on until the move is under a micrometre (at most ``iterations`` moves). A
        calibration error alone moves no goal (the goal image goes through the same camera);
        noise does. The true goal where the pose cannot be solved (fewer than three
        landmarks). No random draw: the episode is the same with or without it.
        """
        pose = np.array(setup.episode.goal, dtype=np.float64)
        for _ in range(iterations):
            points, visible = self.image(setup, pose, "current", None)
            mask = visible & setup.goal_visible
            relative, valid = solve_goal_pose(points, setup.goal_points, setup.goal_depths, mask)
            if not bool(valid):
                return np.array(setup.episode.goal, dtype=np.float64)
            tx, ty, c, s = (float(v) for v in relative)
            cos_yaw, sin_yaw = math.cos(pose[2]), math.sin(pose[2])
            pose = np.array(
                [
                    pose[0] + cos_yaw * tx - sin_yaw * ty,
                    pose[1] + sin_yaw * tx + cos_yaw * ty,
                    wrap_angle_scalar(pose[2] + math.atan2(s, c)),
                ]
            )
            if math.hypot(tx, ty) < 1e-6 and abs(s) < 1e-6:
                break
        return pose

    def _episode_cameras(
        self, rng: np.random.Generator, mirror: MirrorName | None = None
    ) -> tuple[dict[str, Any], Imperfections | None]:
        """Return the episode's cameras, imperfections drawn where the scenario gives ranges.

        ``mirror`` is the episode's (a scenario that draws it); ``None``: the camera's own. The
        goal image is taken by the same real camera (the same calibration errors; its own pixel
        noise), unless the scenario names a goal camera of its own.
        """
        config = self.config.scenario.config
        current, goal = self.config.scenario.episode_cameras(mirror)
        cameras = {"current": current, "goal": goal}
        ranges = config.camera.imperfection_ranges
        drawn = None
        if ranges is not None:
            drawn = ranges.draw(rng, config.camera.imperfections)
            spec = config.camera if mirror is None else replace(config.camera, mirror=mirror)
            cameras["current"] = spec.build(drawn)
            if config.goal_camera is None:
                cameras["goal"] = cameras["current"]
        goal_spec = config.goal_camera
        if goal_spec is not None and goal_spec.imperfection_ranges is not None:
            goal_drawn = goal_spec.imperfection_ranges.draw(rng, goal_spec.imperfections)
            cameras["goal"] = goal_spec.build(goal_drawn)
        return cameras, drawn

    def _observed(self, landmarks: np.ndarray) -> tuple[np.ndarray, np.ndarray | None]:
        """Return the ``(N, 3)`` landmarks the env observes and which the episode has.

        A scenario that draws its landmark count gives episodes fewer than the most it draws;
        the env's arrays keep the most, filled with copies of the first landmark that no
        camera sees (:meth:`_radius_bounds`, :meth:`image`). ``None``: every one is present.
        """
        n = self.config.scenario.n_landmarks
        if len(landmarks) == n:
            return landmarks, None
        present = np.arange(n) < len(landmarks)
        filled = np.concatenate([landmarks, np.repeat(landmarks[:1], n - len(landmarks), 0)])
        return filled, present

    def _radius_bounds(
        self, which: str, camera: Any, heights: np.ndarray, present: np.ndarray | None
    ) -> tuple[np.ndarray, np.ndarray] | None:
        """Return the camera's visible distance interval per landmark height (None: imperfect).

        Cached per camera for scenarios with fixed landmarks and camera height (the same
        heights every episode). An absent landmark (``present`` False) gets an empty interval.
        """
        if camera.imperfections.any:
            return None
        config = self.config.scenario.config
        fixed = config.random_landmarks is None and len(set(config.camera_height_range)) == 1
        fixed = fixed and len(config.mirrors) <= 1
        if not fixed:
            lo, hi = camera.visible_radius_bounds(heights)
            if present is not None:
                lo, hi = np.where(present, lo, np.inf), np.where(present, hi, -np.inf)
            return lo, hi
        if which not in self._bounds_cache:
            self._bounds_cache[which] = camera.visible_radius_bounds(heights)
        return self._bounds_cache[which]

    def _draw_episode(
        self, rng: np.random.Generator, task: int | None, options: dict[str, Any]
    ) -> Episode:
        """Draw an episode from the scenario, with the start and goal ``options`` applied."""
        episode = self.config.scenario.sample(rng, task=task, reach=self._start_reach)
        for key in ("start", "goal"):
            if key in options:
                pose = np.asarray(options[key], dtype=np.float64)
                if pose.shape != (3,) or not np.isfinite(pose).all():
                    raise ValueError(f"options[{key!r}] must be (x, y, yaw), got {options[key]!r}")
                # the same check in every backend, before any physics sees the pose
                if footprint_collides(pose, self.config.robot, episode.room, episode.obstacles):
                    raise ValueError(f"options[{key!r}]: {start_pose_error(pose, key)}")
                episode = (
                    episode._replace(start=pose) if key == "start" else episode._replace(goal=pose)
                )
        goal = episode.goal.astype(np.float64).copy()
        goal[2] = wrap_angle_scalar(float(goal[2]))
        return episode._replace(goal=goal)

    def image(
        self, setup: EpisodeSetup, pose: np.ndarray, which: str, rng: np.random.Generator | None
    ) -> tuple[np.ndarray, np.ndarray]:
        """Normalised image points ``(N, 2)`` (zeros where hidden) and visibility ``(N,)``.

        An ideal camera gives eq. (9) exactly (:func:`~radial_ibvs_gym.envs.radial_image`);
        a camera with imperfections is simulated as the paper's set-up measures
        (:func:`~radial_ibvs_gym.camera.measurement.camera_image`, pixel noise from ``rng``).

        Parameters
        ----------
        setup
            The episode.
        pose
            ``(3,)`` robot pose, metres and radians.
        which
            ``"current"`` (the scenario's camera) or ``"goal"`` (its goal camera).
        rng
            The env's generator (pixel noise); ``None``: the noise-free image.

        The goal image through a camera with imperfections averages ``goal_image_frames``
        noisy frames; they are kept in ``setup.goal_frames``.
        """
        bounds = setup.radius_bounds[which]
        if bounds is not None:
            return radial_image(setup.landmarks_c, bounds[0], bounds[1], pose)
        camera = setup.cameras[which]
        h = setup.episode.camera_height
        p_cam = world_to_camera(setup.points_w, pose, h, validate=False)
        frames = self.config.goal_image_frames if which == "goal" else 1
        if frames == 1:
            points, visible = camera_image(camera, p_cam, rng)
            if setup.present is not None:
                visible &= setup.present
                points[~visible] = 0.0
            return points, visible
        # a robot parked at the goal grabs many noisy frames: each landmark's mean direction
        # over the frames that see it (seen in at least half of them). One batched projection
        # of the frames draws the noise as that many calls of camera_image would, in order
        shots, seen_by = camera_images(
            [camera] * frames, np.broadcast_to(p_cam, (frames, *p_cam.shape)), [rng] * frames
        )
        setup.goal_frames = (shots, seen_by)
        seen = np.sum(seen_by, axis=0)
        total = np.sum(shots, axis=0)
        visible = seen * 2 >= frames
        if setup.present is not None:
            visible &= setup.present
        norm = np.linalg.norm(total, axis=-1, keepdims=True)
        points = np.where(visible[:, None], total / np.maximum(norm, 1e-300), 0.0)
        return points, visible

    def map_observation(self, episode: Episode) -> dict[str, np.ndarray]:
        """Return the privileged map of an episode (metres, world frame, zero-padded).

        ``room`` ``(2,)`` width and depth; ``obstacles`` ``(K, 3)`` rows ``(x, y, radius)``
        (radius 0: none); ``landmarks`` ``(L, 3)`` their positions; ``landmark_range``
        ``(L, 2)`` the interval of horizontal distances at which the nominal camera sees each
        landmark (``(0, 0)``: a padded slot; 1000 stands for no upper bound).
        """
        obstacles = np.zeros((self.config.map_obstacles, 3))
        given = np.asarray(episode.obstacles, dtype=np.float64).reshape(-1, 3)
        obstacles[: len(given)] = given
        n = self.config.scenario.n_landmarks
        k = n if self.config.slots is None else self.config.slots.m
        landmarks = np.asarray(episode.landmarks, dtype=np.float64)
        padded = np.zeros((k, 3))
        padded[: len(landmarks)] = landmarks
        ranges = np.zeros((k, 2))
        heights = landmarks[:, 2] - episode.camera_height
        bounds = self._nominal_camera(episode.mirror).visible_radius_bounds(heights)
        if bounds is not None:  # an on-axis convex mirror (every shipped camera)
            ranges[: len(landmarks), 0] = bounds[0]
            ranges[: len(landmarks), 1] = np.minimum(bounds[1], 1e3)
        else:
            ranges[: len(landmarks), 1] = 1e3
        return {
            "room": np.asarray(episode.room, dtype=np.float64).copy(),
            "obstacles": obstacles,
            "landmarks": padded,
            "landmark_range": ranges,
        }

    def _nominal_camera(self, mirror: MirrorName | None) -> Any:
        """Return the episode's camera without imperfections: what the map's owner knows.

        ``mirror``: the episode's (``None``: the scenario's camera). Built once per mirror.
        """
        if mirror not in self._nominal:
            spec = self.config.scenario.config.camera
            spec = spec if mirror is None else replace(spec, mirror=mirror)
            self._nominal[mirror] = spec.build(Imperfections())
        return self._nominal[mirror]
