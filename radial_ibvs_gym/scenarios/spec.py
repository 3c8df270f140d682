"""Scenario configurations: room, landmarks, camera, start and goal distributions.

A scenario is data (``configs/scenarios/<name>.yaml``), validated on load: unknown keys are
rejected, values checked, and a scene whose goal image shows fewer than
``min_visible_at_goal`` landmarks is refused with a message.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np

from radial_ibvs_gym.camera import CameraSpec
from radial_ibvs_gym.limits import MAX_LANDMARKS, MAX_OBSTACLES, MAX_WORLD_M

__all__ = [
    "MirrorName",
    "PoseRange",
    "RandomLandmarks",
    "RandomObstacles",
    "RandomRoom",
    "ScenarioConfig",
    "TaskSpec",
]

Pose = tuple[float, float, float]
#: a mirror's name, as ``camera.mirror`` takes it
MirrorName = Literal["A", "B"]


def _check_world(values: Any, name: str) -> None:
    """Refuse a length or coordinate that is not finite or lies beyond ``MAX_WORLD_M`` metres."""
    for v in values:
        if not (math.isfinite(v) and abs(v) <= MAX_WORLD_M):
            raise ValueError(
                f"{name} must be finite and within +-MAX_WORLD_M = {MAX_WORLD_M} m, got {values!r}"
            )


def _check_range(
    value: tuple[float, float], name: str, *, positive: bool = False, metres: bool = True
) -> None:
    lo, hi = value
    if not (math.isfinite(lo) and math.isfinite(hi) and lo <= hi):
        raise ValueError(
            f"{name} must be a finite range [low, high] with low <= high, got {value!r}"
        )
    if positive and lo <= 0:
        raise ValueError(f"{name} must be positive, got {value!r}")
    if metres:
        _check_world(value, name)


@dataclass(frozen=True, kw_only=True)
class PoseRange:
    """Uniform distribution of planar poses (a coordinate with ``low == high`` is fixed).

    Attributes
    ----------
    x, y
        ``[low, high]`` ranges of the position, metres (world frame).
    yaw
        ``[low, high]`` range of the heading, radians.
    """

    x: tuple[float, float]
    y: tuple[float, float]
    yaw: tuple[float, float] = (-math.pi, math.pi)

    def __post_init__(self) -> None:
        for name in ("x", "y"):
            _check_range(getattr(self, name), name)
        _check_range(self.yaw, "yaw", metres=False)

    def sample(self, rng: np.random.Generator) -> np.ndarray:
        """Draw one pose ``(x, y, yaw)`` (metres, radians)."""
        lows = np.array([self.x[0], self.y[0], self.yaw[0]])
        highs = np.array([self.x[1], self.y[1], self.yaw[1]])
        return np.asarray(rng.uniform(lows, highs), dtype=np.float64)


@dataclass(frozen=True, kw_only=True)
class TaskSpec:
    """One parking task: where the robot starts and the pose it must reach.

    Attributes
    ----------
    start, goal
        A fixed pose ``[x, y, yaw]`` (metres, radians), a :class:`PoseRange`, or
        ``"anywhere"`` (uniform in the room, ``wall_clearance`` from the walls, any heading).
    """

    start: Pose | PoseRange | Literal["anywhere"]
    goal: Pose | PoseRange | Literal["anywhere"]

    def __post_init__(self) -> None:
        for name in ("start", "goal"):
            value = getattr(self, name)
            if isinstance(value, tuple):
                if not all(math.isfinite(v) for v in value):
                    raise ValueError(f"{name} must be finite, got {value!r}")
                _check_world(value[:2], f"{name} (x, y)")


@dataclass(frozen=True, kw_only=True)
class RandomRoom:
    """Rectangular rooms of random size.

    Attributes
    ----------
    width, depth
        ``[low, high]`` ranges of the room's extent along x and y, metres.
    """

    width: tuple[float, float] = (6.0, 12.0)
    depth: tuple[float, float] = (6.0, 12.0)

    def __post_init__(self) -> None:
        _check_range(self.width, "width", positive=True)
        _check_range(self.depth, "depth", positive=True)


@dataclass(frozen=True, kw_only=True)
class RandomObstacles:
    """Circular obstacles (pillars, boxes) drawn on the floor of each episode's room.

    Attributes
    ----------
    count
        ``[low, high]`` range of the number of obstacles (integers, drawn uniformly).
    radius
        ``[low, high]`` range of their radius, metres.
    clearance
        Smallest gap between an obstacle and a wall, metres (a robot can pass).
    """

    count: tuple[int, int] = (1, 3)
    radius: tuple[float, float] = (0.2, 0.5)
    clearance: float = 0.8

    def __post_init__(self) -> None:
        lo, hi = self.count
        if not (isinstance(lo, int) and isinstance(hi, int) and 0 <= lo <= hi):
            raise ValueError(
                f"count must be a [low, high] range of integers >= 0, got {self.count!r}"
            )
        if hi > MAX_OBSTACLES:
            raise ValueError(f"count must be at most MAX_OBSTACLES = {MAX_OBSTACLES}, got {hi}")
        _check_range(self.radius, "radius", positive=True)
        if not (math.isfinite(self.clearance) and self.clearance >= 0):
            raise ValueError(f"clearance must be finite and >= 0, got {self.clearance!r}")


@dataclass(frozen=True, kw_only=True)
class RandomLandmarks:
    """Landmarks drawn uniformly on the room's walls.

    Attributes
    ----------
    count
        Number of landmarks (>= 3: the paper's features need at least 3 points), or a
        ``[low, high]`` range of integers drawn uniformly per episode. The envs observe
        ``high`` landmarks; those an episode does not draw are never visible (and masked out
        of ``landmark_mask`` with ``max_landmarks``).
    height
        ``[low, high]`` range of their height above the floor, metres.
    """

    count: int | tuple[int, int] = 8
    height: tuple[float, float] = (0.2, 2.4)

    def __post_init__(self) -> None:
        lo, hi = self.count_range
        if not (isinstance(lo, int) and isinstance(hi, int)) or isinstance(lo, bool):
            raise ValueError(f"count must be an integer or a [low, high] range, got {self.count!r}")
        if not 3 <= lo <= hi:
            raise ValueError(f"count must be >= 3 landmarks (low <= high), got {self.count!r}")
        if hi > MAX_LANDMARKS:
            raise ValueError(
                f"count must be at most MAX_LANDMARKS = {MAX_LANDMARKS}, got {self.count!r}"
            )
        _check_range(self.height, "height")

    @property
    def count_range(self) -> tuple[int, int]:
        """The ``(low, high)`` landmark counts (``low == high`` for a fixed count)."""
        return (self.count, self.count) if isinstance(self.count, int) else self.count

    @property
    def most(self) -> int:
        """The largest number of landmarks an episode draws (the envs' landmark axis)."""
        return self.count_range[1]


@dataclass(frozen=True, kw_only=True)
class ScenarioConfig:
    """Everything that defines a family of parking episodes.

    Attributes
    ----------
    name
        Scenario name.
    description
        One paragraph for humans.
    room
        ``[width, depth]`` of the rectangular room ``[0, width] x [0, depth]``, metres, unless
        ``random_room`` is set.
    random_room
        Draw the room size per episode instead.
    obstacles
        Circular obstacles ``[[x, y, radius], ...]`` on the floor, metres.
    random_obstacles
        Also draw circular obstacles per episode (:class:`RandomObstacles`).
    landmarks
        Fixed landmarks ``[[x, y, z], ...]`` in the world frame, metres, unless
        ``random_landmarks`` is set.
    random_landmarks
        Draw landmarks on the walls per episode instead.
    tasks
        The parking tasks; ``task=k`` picks one, ``task=None`` draws one per episode.
    min_start_goal_distance, max_start_goal_distance
        Bounds on the start-goal distance of drawn tasks, metres.
    wall_clearance
        Smallest distance from a drawn pose to a wall, metres.
    camera
        The robot's catadioptric camera.
    goal_camera
        Camera that took the goal image, if not ``camera`` (the paper's mirror-swap test).
    mirrors
        Draw the camera's mirror per episode, uniformly, from these (``camera`` with its
        ``mirror`` replaced: :attr:`Episode.mirror <radial_ibvs_gym.scenarios.Episode>`); empty
        (the default): ``camera.mirror``. The goal image goes through the episode's camera unless
        ``goal_camera`` is given.
    camera_height
        Height of the camera's optical centre above the floor, metres, or a ``[low, high]``
        range drawn uniformly per episode (:attr:`Episode.camera_height
        <radial_ibvs_gym.scenarios.Episode>`).
    depth_scale
        Scale error on the goal depths ``d*`` given to the controller (the paper uses 1.3).
    min_visible_at_goal
        Fewest landmarks the goal image must show (>= 3).
    robot
        Overrides of the robot's physical parameters (validated by the physics layer).
    """

    name: str
    description: str = ""
    room: tuple[float, float] = (10.0, 10.0)
    random_room: RandomRoom | None = None
    obstacles: tuple[tuple[float, float, float], ...] = ()
    random_obstacles: RandomObstacles | None = None
    landmarks: tuple[tuple[float, float, float], ...] = ()
    random_landmarks: RandomLandmarks | None = None
    tasks: tuple[TaskSpec, ...] = ()
    min_start_goal_distance: float = 0.0
    max_start_goal_distance: float = math.inf
    wall_clearance: float = 0.5
    camera: CameraSpec = field(default_factory=CameraSpec)
    goal_camera: CameraSpec | None = None
    mirrors: tuple[MirrorName, ...] = ()
    camera_height: float | tuple[float, float] = 1.8
    depth_scale: float = 1.0
    min_visible_at_goal: int = 3
    robot: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        w, d = self.room
        if not (math.isfinite(w) and math.isfinite(d) and w > 0 and d > 0):
            raise ValueError(f"room must be a positive [width, depth] in metres, got {self.room!r}")
        _check_world(self.room, "room")
        if not self.tasks:
            raise ValueError("tasks: a scenario needs at least one task (start and goal)")
        if bool(self.landmarks) == (self.random_landmarks is not None):
            raise ValueError("give exactly one of landmarks (fixed) and random_landmarks")
        if len(self.landmarks) > MAX_LANDMARKS:
            raise ValueError(
                f"landmarks: {len(self.landmarks)} exceed MAX_LANDMARKS = {MAX_LANDMARKS}"
            )
        drawn = self.random_obstacles.count[1] if self.random_obstacles is not None else 0
        if len(self.obstacles) + drawn > MAX_OBSTACLES:
            raise ValueError(
                f"obstacles: {len(self.obstacles)} fixed and up to {drawn} drawn exceed "
                f"MAX_OBSTACLES = {MAX_OBSTACLES}"
            )
        for i, obstacle in enumerate(self.obstacles):
            _check_world(obstacle, f"obstacles[{i}]")
            if not obstacle[2] > 0:
                raise ValueError(f"obstacles[{i}] radius must be positive, got {obstacle[2]!r}")
        for i, p in enumerate(self.landmarks):
            _check_world(p, f"landmarks[{i}]")
        lo, hi = self.min_start_goal_distance, self.max_start_goal_distance
        if not (lo >= 0 and hi > lo):
            raise ValueError(
                f"need 0 <= min_start_goal_distance < max_start_goal_distance, got {lo!r}, {hi!r}"
            )
        for name in ("wall_clearance", "depth_scale"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be finite and positive, got {value!r}")
        _check_world((self.wall_clearance,), "wall_clearance")
        _check_range(self.camera_height_range, "camera_height", positive=True)
        if len(set(self.mirrors)) != len(self.mirrors):
            raise ValueError(f"mirrors must not repeat a mirror, got {list(self.mirrors)!r}")
        smallest = (
            min(self.random_room.width[0], self.random_room.depth[0])
            if self.random_room is not None
            else min(self.room)
        )
        if 2.0 * self.wall_clearance >= smallest:
            raise ValueError(
                f"wall_clearance={self.wall_clearance!r} m leaves no floor in a room as small as "
                f"{smallest!r} m (it must be under half the room's smallest side)"
            )
        if self.min_visible_at_goal < 3:
            raise ValueError(f"min_visible_at_goal must be >= 3, got {self.min_visible_at_goal!r}")
        n = len(self.landmarks) if self.landmarks else self.random_landmarks.count_range[0]  # type: ignore[union-attr]
        if self.min_visible_at_goal > n:
            raise ValueError(
                f"min_visible_at_goal={self.min_visible_at_goal} exceeds the {n} landmarks"
            )

    @property
    def camera_height_range(self) -> tuple[float, float]:
        """The ``(low, high)`` camera heights, metres (``low == high`` for a fixed height)."""
        h = self.camera_height
        return (h, h) if isinstance(h, int | float) else (float(h[0]), float(h[1]))

    def fixed_camera_height(self, needs: str) -> float:
        """Return the camera height of a scenario that fixes it, metres.

        Parameters
        ----------
        needs
            What needs one height for every episode (named in the error).

        Raises
        ------
        ValueError
            If the scenario draws the height per episode (a ``[low, high]`` range): then read
            each episode's :attr:`~radial_ibvs_gym.scenarios.Episode.camera_height`.
        """
        lo, hi = self.camera_height_range
        if lo != hi:
            raise ValueError(
                f"scenario {self.name!r} draws camera_height per episode ({[lo, hi]} m); "
                f"{needs} needs one fixed height"
            )
        return float(lo)
