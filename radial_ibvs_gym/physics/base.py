"""The interface and the shared state of the physics backends."""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from radial_ibvs_gym.physics.diffdrive import RobotConfig

__all__ = ["StepResult", "World", "check_obstacles"]


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
        self._velocity = np.zeros(2)
        self._time = 0.0
        self._n_collisions = 0

    @staticmethod
    def _check_pose(pose: ArrayLike) -> NDArray[np.float64]:
        p = np.asarray(pose, dtype=np.float64)
        if p.shape != (3,) or not np.isfinite(p).all():
            raise ValueError(f"pose must be three finite numbers (x, y, yaw), got {pose!r}")
        return p

    def _finish_step(self, velocity: NDArray[np.float64], dt: float, collision: bool) -> StepResult:
        self._velocity = velocity
        self._time += dt
        self._n_collisions += int(collision)
        return StepResult(self.pose, velocity.copy(), collision, self._n_collisions)

    @property
    @abstractmethod
    def pose(self) -> NDArray[np.float64]:
        """Current pose ``(x, y, yaw)``, metres and radians in ``[-pi, pi)`` (a copy)."""

    @property
    def velocity(self) -> NDArray[np.float64]:
        """Velocity ``(v, omega)`` applied over the last step, m/s and rad/s (a copy)."""
        return self._velocity.copy()

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
