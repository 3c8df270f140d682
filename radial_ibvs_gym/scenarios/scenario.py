"""Drawing episodes from a scenario: room, landmarks, start and goal poses."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from radial_ibvs_gym.camera import CatadioptricCamera
from radial_ibvs_gym.config import (
    ConfigError,
    config_path,
    configs_dir,
    did_you_mean,
    load_yaml,
    short,
)
from radial_ibvs_gym.geometry import world_to_camera
from radial_ibvs_gym.scenarios.spec import MirrorName, PoseRange, ScenarioConfig

__all__ = ["Episode", "Scenario", "load_scenario"]

#: Attempts at drawing a valid episode before giving up with an error.
MAX_TRIES = 1000


_NO_OBSTACLES = np.zeros((0, 3))
_NO_OBSTACLES.setflags(write=False)


class Episode(NamedTuple):
    """One drawn episode (world frame, metres and radians).

    Attributes
    ----------
    task
        Index of the task in the scenario.
    room
        ``(2,)`` width and depth of the room ``[0, width] x [0, depth]``.
    landmarks
        ``(N, 3)`` landmark positions.
    start, goal
        ``(3,)`` poses ``(x, y, yaw)``.
    obstacles
        ``(K, 3)`` circular obstacles ``(x, y, radius)`` of this episode: the scenario's fixed
        ones, then the drawn ones.
    camera_height
        Height of the camera's optical centre above the floor in this episode, metres (drawn
        when the scenario gives a range).
    mirror
        The camera's mirror in this episode, where the scenario draws it (``mirrors``);
        ``None``: the scenario's camera.
    """

    task: int
    room: np.ndarray
    landmarks: np.ndarray
    start: np.ndarray
    goal: np.ndarray
    obstacles: np.ndarray = _NO_OBSTACLES
    camera_height: float = 1.8
    mirror: MirrorName | None = None


class Scenario:
    """A validated scenario with its cameras built, ready to draw episodes.

    Parameters
    ----------
    config
        The scenario's configuration.

    Raises
    ------
    ValueError
        If a fixed goal (with fixed landmarks) shows fewer than ``min_visible_at_goal``
        landmarks, or a fixed start shows fewer than that.
    """

    def __init__(self, config: ScenarioConfig) -> None:
        self.config = config
        #: the fixed landmarks as an array (None for random ones), converted once
        self._fixed_landmarks = (
            np.array(config.landmarks, dtype=np.float64) if config.landmarks else None
        )
        self._bounds: dict[tuple[int, float], tuple[np.ndarray, np.ndarray] | None] = {}
        self.camera: CatadioptricCamera = config.camera.build()
        self.goal_camera: CatadioptricCamera = (
            config.goal_camera.build() if config.goal_camera is not None else self.camera
        )
        #: the camera with each mirror the scenario draws from (``mirrors``)
        self.cameras_by_mirror: dict[MirrorName, CatadioptricCamera] = {
            m: replace(config.camera, mirror=m).build() for m in config.mirrors
        }
        if config.landmarks and config.random_room is None:
            for k, task in enumerate(config.tasks):
                for which, spec, cam in (
                    ("goal", task.goal, self.goal_camera),
                    ("start", task.start, self.camera),
                ):
                    fixed = config.camera_height_range[0] == config.camera_height_range[1]
                    if isinstance(spec, tuple) and fixed and not config.mirrors:
                        n = int(self.visible(np.array(spec), cam=cam).sum())
                        if n < config.min_visible_at_goal:
                            raise ValueError(
                                f"scenario {config.name!r}, task {k}: only {n} of "
                                f"{len(config.landmarks)} landmarks are visible at the {which} "
                                f"pose {list(spec)}; at least {config.min_visible_at_goal} are "
                                "needed (min_visible_at_goal)"
                            )

    @property
    def n_tasks(self) -> int:
        """Number of tasks."""
        return len(self.config.tasks)

    @property
    def n_landmarks(self) -> int:
        """Number of landmarks the envs observe: the most an episode draws.

        An episode that draws fewer (a ``random_landmarks.count`` range) fills the rest with
        landmarks that are never visible (:class:`~radial_ibvs_gym.envs.episodes.EpisodeSetup`).
        """
        c = self.config
        return len(c.landmarks) if c.landmarks else c.random_landmarks.most  # type: ignore[union-attr]

    def visible(
        self,
        pose: np.ndarray,
        landmarks: np.ndarray | None = None,
        cam: CatadioptricCamera | None = None,
        camera_height: float | None = None,
    ) -> np.ndarray:
        """Visibility mask ``(N,)`` of the landmarks from a robot pose ``(x, y, yaw)``.

        ``camera_height`` (metres) defaults to the scenario's, which must then be fixed.
        """
        pts = np.asarray(self.config.landmarks) if landmarks is None else landmarks
        if camera_height is None:
            camera_height = self.config.fixed_camera_height("Scenario.visible without a height")
        p_cam = world_to_camera(pts, pose, camera_height)
        return (cam or self.camera).visible(p_cam)

    def _visible_count(
        self, pose: np.ndarray, landmarks: np.ndarray, cam: CatadioptricCamera, height: float
    ) -> int:
        """Count what :meth:`visible` sees, for the arrays :meth:`sample` made.

        An on-axis camera sees a landmark iff its horizontal distance lies in an interval set
        by its height (:meth:`CatadioptricCamera.visible_radius_bounds`): computed once for
        fixed landmarks and height, then two comparisons per landmark.
        """
        heights = landmarks[:, 2] - height
        key = (id(cam), height)
        if self._fixed_landmarks is None or key not in self._bounds:
            if self._fixed_landmarks is not None and len(self._bounds) >= 64:
                self._bounds.clear()  # drawn heights: a bounded cache
            self._bounds[key] = cam.visible_radius_bounds(heights)
        bounds = self._bounds[key]
        if bounds is None:  # tilted, off-axis or concave: the exact test
            p_cam = world_to_camera(landmarks, pose, height, validate=False)
            return int(np.count_nonzero(cam.visible(p_cam, validate=False)))
        rho = np.hypot(landmarks[:, 0] - pose[0], landmarks[:, 1] - pose[1])
        return int(np.count_nonzero((rho > bounds[0]) & (rho < bounds[1])))

    def _pose(self, spec: Any, room: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        if isinstance(spec, PoseRange):
            return spec.sample(rng)
        if spec == "anywhere":
            c = self.config.wall_clearance
            return rng.uniform([c, c, -np.pi], [room[0] - c, room[1] - c, np.pi])
        return np.array(spec, dtype=np.float64)

    def check_reach(
        self, reach: float, tasks: Sequence[int] | None = None, name: str = "reach"
    ) -> float:
        """Validate a start reach (:meth:`sample`) for ``tasks`` (default: all); return it.

        Raises
        ------
        ValueError
            Unless ``reach`` is a number in ``(0, 1]``, and 1 for tasks with a fixed start.
        """
        if isinstance(reach, bool) or not (isinstance(reach, int | float) and 0.0 < reach <= 1.0):
            raise ValueError(f"{name} must be a number in (0, 1], got {reach!r}")
        tasks = range(self.n_tasks) if tasks is None else tasks
        fixed = [t for t in tasks if self.config.tasks[t].start != "anywhere"]
        if reach < 1.0 and fixed:
            raise ValueError(
                f"{name} < 1 needs a start 'anywhere' (got {reach!r}); scenario "
                f"{self.config.name!r} fixes the start of task(s) {fixed}"
            )
        return float(reach)

    def _near(
        self, goal: np.ndarray, room: np.ndarray, reach: float, rng: np.random.Generator
    ) -> np.ndarray:
        """Draw a start around ``goal``: ``reach`` times the distance bounds and half-turn."""
        c = self.config
        far = c.max_start_goal_distance
        if not math.isfinite(far):
            far = float(np.hypot(*room))
        distance = rng.uniform(reach * c.min_start_goal_distance, reach * far)
        direction = rng.uniform(-np.pi, np.pi)
        heading = goal[2] + rng.uniform(-reach * np.pi, reach * np.pi)
        return np.array(
            [
                goal[0] + distance * np.cos(direction),
                goal[1] + distance * np.sin(direction),
                (heading + np.pi) % (2.0 * np.pi) - np.pi,
            ]
        )

    def _landmarks(self, room: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        spec = self.config.random_landmarks
        if spec is None:
            assert self._fixed_landmarks is not None
            return self._fixed_landmarks.copy()
        # a count (drawn only for a range), a point on the perimeter, uniform in arc length,
        # then a height
        lo, hi = spec.count_range
        count = lo if lo == hi else int(rng.integers(lo, hi + 1))
        w, d = room
        u = rng.uniform(0.0, 2.0 * (w + d), count)
        x = np.select([u < w, u < w + d, u < 2 * w + d], [u, w, 2 * w + d - u], 0.0)
        y = np.select([u < w, u < w + d, u < 2 * w + d], [0.0, u - w, d], 2 * (w + d) - u)
        z = rng.uniform(*spec.height, count)
        return np.stack([x, y, z], axis=-1)

    def _inside(self, pose: np.ndarray, room: np.ndarray, obstacles: np.ndarray) -> bool:
        """Whether ``pose`` is ``wall_clearance`` away from the walls and the obstacles."""
        c = self.config.wall_clearance
        if not (c <= pose[0] <= room[0] - c and c <= pose[1] <= room[1] - c):
            return False
        return all(
            math.hypot(pose[0] - ox, pose[1] - oy) >= radius + c for ox, oy, radius in obstacles
        )

    def _obstacles(self, room: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        """Return the fixed obstacles, then (``random_obstacles``) drawn ones inside the room.

        Drawn obstacles keep ``clearance`` from the walls and from each other; draws that do
        not fit are dropped. Nothing is drawn without ``random_obstacles`` (the random stream
        of such scenarios is unchanged).
        """
        fixed = np.array(self.config.obstacles, dtype=np.float64).reshape(-1, 3)
        spec = self.config.random_obstacles
        if spec is None:
            return fixed
        count = int(rng.integers(spec.count[0], spec.count[1] + 1))
        radii = rng.uniform(*spec.radius, count)
        drawn: list[np.ndarray] = []
        for radius in radii:
            margin = radius + spec.clearance
            if room[0] <= 2 * margin or room[1] <= 2 * margin:
                continue
            centre = rng.uniform([margin, margin], [room[0] - margin, room[1] - margin])
            others = [*fixed, *drawn]
            if all(
                math.hypot(centre[0] - o[0], centre[1] - o[1]) >= radius + o[2] + spec.clearance
                for o in others
            ):
                drawn.append(np.array([centre[0], centre[1], radius]))
        return np.concatenate([fixed, np.array(drawn).reshape(-1, 3)])

    def sample(
        self, rng: np.random.Generator, task: int | None = None, reach: float = 1.0
    ) -> Episode:
        """Draw an episode.

        Parameters
        ----------
        rng
            The random generator (the env's ``np_random``).
        task
            Task index; ``None`` draws one uniformly.
        reach
            In ``(0, 1]``: the fraction of the start distribution used, for a reverse
            curriculum. At ``1`` (default) the start is drawn as the scenario says. Below,
            the goal is drawn first and the start around it: at a distance drawn uniformly in
            ``reach`` times the scenario's distance bounds (metres; the room's diagonal stands
            for an unbounded maximum), in any direction, with a heading within
            ``reach * pi`` radians of the goal's. Only for tasks whose start is ``anywhere``.

        Returns
        -------
        Episode
            A start and goal inside the room, within the distance bounds, with at least
            ``min_visible_at_goal`` landmarks visible at both.

        Raises
        ------
        ValueError
            For a task index out of range, or when no valid episode was found in
            ``MAX_TRIES`` draws (the scenario is too constrained).
        """
        c = self.config
        if task is None:
            task = int(rng.integers(self.n_tasks))
        elif not (isinstance(task, (int, np.integer)) and 0 <= task < self.n_tasks):
            raise ValueError(f"task must be in 0..{self.n_tasks - 1}, got {task!r}")
        spec = c.tasks[task]
        reach = self.check_reach(reach, [task])
        for _ in range(MAX_TRIES):
            room = (
                np.array([rng.uniform(*c.random_room.width), rng.uniform(*c.random_room.depth)])
                if c.random_room is not None
                else np.array(c.room, dtype=np.float64)
            )
            landmarks = self._landmarks(room, rng)
            lo, hi = c.camera_height_range
            height = lo if lo == hi else float(rng.uniform(lo, hi))  # drawn only for a range
            mirror = self._mirror(rng)
            camera, goal_camera = self.episode_cameras(mirror)
            obstacles = self._obstacles(room, rng)
            if reach < 1.0:
                goal = self._pose(spec.goal, room, rng)
                start = self._near(goal, room, reach, rng)
            else:
                start = self._pose(spec.start, room, rng)
                goal = self._pose(spec.goal, room, rng)
            dist = float(np.hypot(*(goal[:2] - start[:2])))
            if not (self._inside(start, room, obstacles) and self._inside(goal, room, obstacles)):
                continue
            if reach == 1.0 and not (
                c.min_start_goal_distance <= dist <= c.max_start_goal_distance
            ):  # below 1, _near drew the distance within the scaled bounds
                continue
            need = c.min_visible_at_goal
            if self._visible_count(goal, landmarks, goal_camera, height) < need:
                continue
            if self._visible_count(start, landmarks, camera, height) < need:
                continue
            return Episode(task, room, landmarks, start, goal, obstacles, float(height), mirror)
        raise ValueError(
            f"scenario {c.name!r}: no valid episode in {MAX_TRIES} draws (poses inside the room, "
            f"start-goal distance in [{c.min_start_goal_distance}, {c.max_start_goal_distance}] "
            f"m, >= {c.min_visible_at_goal} landmarks visible): relax the scenario"
        )

    def _mirror(self, rng: np.random.Generator) -> MirrorName | None:
        """Draw an episode's mirror (``mirrors``; one listed: that one, with no draw)."""
        mirrors = self.config.mirrors
        if not mirrors:
            return None
        return mirrors[0] if len(mirrors) == 1 else mirrors[int(rng.integers(len(mirrors)))]

    def episode_cameras(
        self, mirror: MirrorName | None
    ) -> tuple[CatadioptricCamera, CatadioptricCamera]:
        """Return the current and goal cameras of an episode with ``mirror``.

        ``None``: the scenario's. Without the imperfections drawn per episode.
        """
        if mirror is None:
            return self.camera, self.goal_camera
        camera = self.cameras_by_mirror[mirror]
        return camera, (self.goal_camera if self.config.goal_camera is not None else camera)

    def goal_depths(self, episode: Episode) -> np.ndarray:
        """Goal depths ``d*`` (horizontal distances at the goal, metres), times ``depth_scale``.

        This is the only 3D knowledge the paper's controller may use (Section 4.1).
        """
        p = world_to_camera(episode.landmarks, episode.goal, episode.camera_height, validate=False)
        return self.config.depth_scale * np.hypot(p[:, 0], p[:, 1])


def load_scenario(name_or_path: str | Path, **overrides: Any) -> Scenario:
    """Load a scenario by shipped name (``configs/scenarios/<name>.yaml``) or from a path.

    Parameters
    ----------
    name_or_path
        ``"paper-sim"``, ``"paper-lab"``, ``"random"``, or a path to a YAML file.
    **overrides
        Top-level keys replacing those of the file (e.g. ``depth_scale=1.3``).

    Returns
    -------
    Scenario
        The validated scenario.

    Raises
    ------
    radial_ibvs_gym.config.ConfigError
        For an unknown name, key or bad value.
    ValueError
        For a scene where too few landmarks are visible at a fixed goal or start.
    """
    if not isinstance(name_or_path, str | Path):
        raise ConfigError(
            f"scenario must be a shipped name or the path of a YAML file, got a "
            f"{type(name_or_path).__name__}: {short(name_or_path)}"
        )
    path = Path(name_or_path)
    if path.suffix not in (".yaml", ".yml"):
        path = config_path("scenarios", str(name_or_path))
    elif not path.is_file():
        shipped = sorted(p.stem for p in (configs_dir() / "scenarios").glob("*.yaml"))
        raise ConfigError(
            f"scenario file {short(str(path))} not found{did_you_mean(path.stem, shipped)}; "
            f"shipped scenarios (by name): {shipped}"
        )
    return Scenario(load_yaml(ScenarioConfig, path, **overrides))
