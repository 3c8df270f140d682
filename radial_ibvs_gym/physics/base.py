"""The interface and the shared state of the physics backends."""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from radial_ibvs_gym.physics.diffdrive import RobotConfig

__all__ = [
    "StepResult",
    "World",
    "check_obstacles",
    "footprint_collides",
    "start_pose_error",
]


class StepResult(NamedTuple):
    """What one control step did.

    Attributes
    ----------
    pose
        ``(3,)`` robot pose ``(x, y, yaw)`` after the step, metres and radians in ``[-pi, pi)``.
    velocity
        ``(2,)`` the ``(v, omega)`` applied after the limits, m/s and rad/s.
    collision
        Whether the robot touched a wall or an obstacle during this step.
    n_collisions
        Number of steps with a collision since the last reset.
    """

    pose: NDArray[np.float64]
    velocity: NDArray[np.float64]
    collision: bool
    n_collisions: int


def check_obstacles(
    obstacles: tuple[tuple[float, float, float], ...],
) -> tuple[tuple[float, float, float], ...]:
    """Validate circular obstacles ``(x, y, radius)`` (metres) and return them as floats."""
    out = []
    for i, obstacle in enumerate(obstacles):
        values = tuple(float(v) for v in obstacle)
        if len(values) != 3 or not all(math.isfinite(v) for v in values) or values[2] <= 0:
            raise ValueError(f"obstacles[{i}] must be (x, y, radius > 0), got {obstacle!r}")
        out.append((values[0], values[1], values[2]))
    return tuple(out)


def footprint_collides(
    pose: ArrayLike,
    robot: RobotConfig,
    room: tuple[float, float] | ArrayLike,
    obstacles: ArrayLike = (),
) -> bool:
    """Whether the robot's footprint at ``pose`` leaves the room or overlaps an obstacle.

    Parameters
    ----------
    pose
        ``(3,)`` pose ``(x, y, yaw)``, metres and radians.
    robot
        The robot (its ``length`` x ``width`` rectangle is the footprint, centred on ``pose``).
    room
        ``(width, depth)`` of the room ``[0, width] x [0, depth]``, metres.
    obstacles
        ``(K, 3)`` circular obstacles ``(x, y, radius)``, metres.
    """
    x, y, th = np.asarray(pose, dtype=np.float64).tolist()
    hl, hw = 0.5 * robot.length, 0.5 * robot.width
    c, s = abs(math.cos(th)), abs(math.sin(th))
    ex, ey = c * hl + s * hw, s * hl + c * hw  # half extents of the rotated footprint
    w, d = (float(v) for v in np.asarray(room, dtype=np.float64).tolist())
    if not (x - ex >= 0.0 and y - ey >= 0.0 and x + ex <= w and y + ey <= d):
        return True
    cos, sin = math.cos(th), math.sin(th)
    for ox, oy, radius in np.asarray(obstacles, dtype=np.float64).reshape(-1, 3).tolist():
        # the obstacle's centre in the robot frame, clamped to the footprint
        u = cos * (ox - x) + sin * (oy - y)
        v = -sin * (ox - x) + cos * (oy - y)
        du, dv = u - min(max(u, -hl), hl), v - min(max(v, -hw), hw)
        if du * du + dv * dv < radius * radius:
            return True
    return False


def start_pose_error(pose: ArrayLike, which: str = "start") -> str:
    """Return the error of a pose whose footprint is not free (the same in every backend)."""
    values = np.asarray(pose, dtype=np.float64).tolist()
    return (
        f"{which} pose {values} puts the robot into a wall of the room or an obstacle, or "
        "outside the room"
    )


class World(ABC):
    """A differential-drive robot in a rectangular room with circular obstacles.

    Parameters
    ----------
    robot
        The robot's parameters (its limits apply to every command).
    room
        ``(width, depth)`` of the room ``[0, width] x [0, depth]``, metres.
    obstacles
        Circular obstacles ``(x, y, radius)``, metres.
    """

    def __init__(
        self,
        robot: RobotConfig,
        room: tuple[float, float],
        obstacles: tuple[tuple[float, float, float], ...] = (),
    ) -> None:
        w, d = (float(v) for v in room)
        if not (w > 0 and d > 0 and math.isfinite(w) and math.isfinite(d)):
            raise ValueError(f"room must be a positive (width, depth), got {room!r}")
        self.robot = robot
        self.room = (w, d)
        self.obstacles = check_obstacles(obstacles)
        self._restart()

    def _restart(self) -> None:
        self._twist = (0.0, 0.0)  # (v, omega) applied over the last step, as floats
        self._time = 0.0
        self._n_collisions = 0

    @staticmethod
    def _check_pose(pose: ArrayLike) -> NDArray[np.float64]:
        p = np.asarray(pose, dtype=np.float64)
        if p.shape != (3,) or not np.isfinite(p).all():
            raise ValueError(f"pose must be three finite numbers (x, y, yaw), got {pose!r}")
        return p

    def colliding(self, pose: ArrayLike) -> bool:
        """Whether the robot's footprint at ``pose`` leaves the room or overlaps an obstacle."""
        return footprint_collides(pose, self.robot, self.room, self.obstacles)

    def _check_start(self, pose: ArrayLike) -> NDArray[np.float64]:
        """Return a start pose as floats if it is finite and the footprint there is free.

        The same check in every backend: the footprint must lie inside the room and clear of
        every obstacle.
        """
        p = self._check_pose(pose)
        if self.colliding(p):
            raise ValueError(start_pose_error(p))
        return p

    def _finish_step(self, twist: tuple[float, float], dt: float, collision: bool) -> StepResult:
        self._twist = twist
        self._time += dt
        self._n_collisions += int(collision)
        return StepResult(self.pose, np.array(twist), collision, self._n_collisions)

    @property
    @abstractmethod
    def pose(self) -> NDArray[np.float64]:
        """Current pose ``(x, y, yaw)``, metres and radians in ``[-pi, pi)`` (a copy)."""

    @property
    def velocity(self) -> NDArray[np.float64]:
        """Velocity ``(v, omega)`` applied over the last step, m/s and rad/s (a copy)."""
        return np.array(self._twist)

    @property
    def time(self) -> float:
        """Seconds simulated since the last reset."""
        return self._time

    @abstractmethod
    def reset(self, pose: ArrayLike) -> None:
        """Place the robot at rest at ``pose`` ``(x, y, yaw)``.

        Raises
        ------
        ValueError
            If the pose is not finite or the robot would overlap a wall or an obstacle there.
        """

    @abstractmethod
    def step(self, command: ArrayLike, dt: float) -> StepResult:
        """Apply ``(v, omega)`` (m/s, rad/s; after the robot's limits) for ``dt`` seconds."""
