"""The ``kinematic`` backend: the exact unicycle model in numpy (no inertia, no contact forces).

Used to reproduce the paper (its simulations are kinematic) and for speed. Collisions with the
walls are detected geometrically and reported, but nothing stops the robot.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from radial_ibvs_gym.geometry import wrap_angle_scalar
from radial_ibvs_gym.physics.diffdrive import RobotConfig, limit_command

__all__ = ["KinematicWorld", "StepResult", "check_obstacles", "integrate_unicycle"]


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


class StepResult(NamedTuple):
    """What one control step did.

    Attributes
    ----------
    pose
        ``(3,)`` robot pose ``(x, y, yaw)`` after the step, metres and radians in ``[-pi, pi)``.
    velocity
        ``(2,)`` the ``(v, omega)`` applied after the limits, m/s and rad/s.
    collision
        Whether the robot's footprint touched a wall during this step (checked at its end).
    n_collisions
        Number of steps with a collision since the last reset.
    """

    pose: NDArray[np.float64]
    velocity: NDArray[np.float64]
    collision: bool
    n_collisions: int


def integrate_unicycle(pose: ArrayLike, v: float, omega: float, dt: float) -> NDArray[np.float64]:
    """Exact pose after moving with constant ``(v, omega)`` for ``dt`` seconds (an arc).

    Parameters
    ----------
    pose
        ``(3,)`` start pose ``(x, y, yaw)``, metres and radians.
    v, omega
        Linear (m/s) and angular (rad/s) speed.
    dt
        Duration, seconds.

    Returns
    -------
    numpy.ndarray
        ``(3,)`` end pose, yaw wrapped to ``[-pi, pi)``.
    """
    x, y, th = (float(c) for c in np.asarray(pose, dtype=np.float64))
    half = 0.5 * omega * dt
    # chord of the arc: v/omega (sin th' - sin th) = v dt sinc(half) cos(th + half), and the
    # same for y; this form has no cancellation for small omega (and is exact for omega = 0)
    chord = v * dt * (math.sin(half) / half if abs(half) > 1e-12 else 1.0 - half * half / 6.0)
    x += chord * math.cos(th + half)
    y += chord * math.sin(th + half)
    return np.array([x, y, wrap_angle_scalar(th + omega * dt)])


class KinematicWorld:
    """A differential-drive robot in a rectangular room, integrated exactly.

    Parameters
    ----------
    robot
        The robot's parameters (limits apply to every command).
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
        self._half = (0.5 * robot.length, 0.5 * robot.width)
        self._pose = np.zeros(3)
        self._velocity = np.zeros(2)
        self._time = 0.0
        self._n_collisions = 0

    @property
    def pose(self) -> NDArray[np.float64]:
        """Current pose ``(x, y, yaw)``, metres and radians (a copy)."""
        return self._pose.copy()

    @property
    def velocity(self) -> NDArray[np.float64]:
        """Velocity ``(v, omega)`` applied over the last step, m/s and rad/s (a copy)."""
        return self._velocity.copy()

    @property
    def time(self) -> float:
        """Seconds simulated since the last reset."""
        return self._time

    def colliding(self, pose: ArrayLike) -> bool:
        """Whether the robot's footprint at ``pose`` leaves the room or overlaps an obstacle."""
        x, y, th = np.asarray(pose, dtype=np.float64).tolist()
        c, s = abs(math.cos(th)), abs(math.sin(th))
        hl, hw = self._half
        ex, ey = c * hl + s * hw, s * hl + c * hw  # half extents of the rotated footprint
        w, d = self.room
        if x - ex < 0.0 or y - ey < 0.0 or x + ex > w or y + ey > d:
            return True
        cos, sin = math.cos(th), math.sin(th)
        for ox, oy, radius in self.obstacles:
            # the obstacle's centre in the robot frame, clamped to the footprint
            u = cos * (ox - x) + sin * (oy - y)
            v = -sin * (ox - x) + cos * (oy - y)
            du, dv = u - min(max(u, -hl), hl), v - min(max(v, -hw), hw)
            if du * du + dv * dv < radius * radius:
                return True
        return False

    def reset(self, pose: ArrayLike) -> None:
        """Place the robot at rest at ``pose`` ``(x, y, yaw)``.

        Raises
        ------
        ValueError
            If the pose is not finite or the robot would overlap a wall there.
        """
        p = np.asarray(pose, dtype=np.float64)
        if p.shape != (3,) or not np.isfinite(p).all():
            raise ValueError(f"pose must be three finite numbers (x, y, yaw), got {pose!r}")
        if self.colliding(p):
            raise ValueError(
                f"start pose {p.tolist()} puts the robot into a wall of the room or an obstacle"
            )
        self._pose = np.array([p[0], p[1], wrap_angle_scalar(float(p[2]))])
        self._velocity = np.zeros(2)
        self._time = 0.0
        self._n_collisions = 0

    def step(self, command: ArrayLike, dt: float) -> StepResult:
        """Apply ``(v, omega)`` (after the robot's limits) for ``dt`` seconds."""
        vel = limit_command(command, self._velocity, dt, self.robot)
        self._pose = integrate_unicycle(self._pose, vel[0], vel[1], dt)
        self._velocity = vel
        self._time += dt
        collision = self.colliding(self._pose)
        self._n_collisions += int(collision)
        return StepResult(self._pose.copy(), vel.copy(), collision, self._n_collisions)
