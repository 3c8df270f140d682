"""The ``kinematic`` backend: the exact unicycle model in numpy (no inertia, no contact forces).

Used to reproduce the paper (its simulations are kinematic) and for speed. Collisions with the
walls are detected geometrically and reported, but nothing stops the robot.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from radial_ibvs_gym.geometry import wrap_angle_scalar
from radial_ibvs_gym.physics.base import StepResult, World
from radial_ibvs_gym.physics.diffdrive import RobotConfig, limited_twist

__all__ = ["KinematicWorld", "integrate_unicycle"]


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


class KinematicWorld(World):
    """The robot integrated exactly as a unicycle; collisions are only detected.

    Parameters are those of :class:`~radial_ibvs_gym.physics.base.World`.
    """

    def __init__(
        self,
        robot: RobotConfig,
        room: tuple[float, float],
        obstacles: tuple[tuple[float, float, float], ...] = (),
    ) -> None:
        super().__init__(robot, room, obstacles)
        self._pose = np.zeros(3)

    @property
    def pose(self) -> NDArray[np.float64]:  # noqa: D102
        return self._pose.copy()

    def reset(self, pose: ArrayLike) -> None:  # noqa: D102
        p = self._check_start(pose)
        self._pose = np.array([p[0], p[1], wrap_angle_scalar(float(p[2]))])
        self._restart()

    def step(self, command: ArrayLike, dt: float) -> StepResult:  # noqa: D102
        twist = limited_twist(command, self._twist, dt, self.robot)
        vel = np.array(twist)  # numpy scalars for the integration, as ever
        self._pose = integrate_unicycle(self._pose, vel[0], vel[1], dt)
        return self._finish_step(twist, dt, self.colliding(self._pose))
