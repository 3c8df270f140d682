"""The smooth control law of Park and Kuipers (ICRA 2011), used by the paper as eq. (38).

For a differential-drive robot heading to a target pose, with egocentric polar coordinates
``r`` (distance to the target), ``phi`` (target orientation with respect to the line of sight)
and ``delta`` (robot heading with respect to the line of sight), the path curvature is

    kappa = -(1 / r) [k_delta (delta - atan(-k_phi phi))
                      + (1 + k_phi / (1 + (k_phi phi)^2)) sin(delta)]

Sign conventions follow ROS 2 nav2's ``nav2_graceful_controller`` (``EgocentricPolarCoordinates``):
the line of sight is ``atan2(-dy, dx)`` and ``phi``, ``delta`` are the target and robot yaws plus
that angle, wrapped to ``[-pi, pi)``; i.e. both angles are measured clockwise from the line of
sight. The paper's eq. (38) lacks the leading minus because it measures them the other way
(``docs/notes-controller.md``, misprint 3). The linear speed follows nav2:
``v = v_max / (1 + beta |kappa|^lambda)``,
slowed within ``slowdown_radius`` of the target, clamped to ``[v_min, v_max]``; ``omega =
kappa v`` is clamped to ``omega_max`` and ``v`` re-derived so the curvature is kept.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from radial_ibvs_gym.geometry import wrap_angle

__all__ = ["SmoothControlLaw", "curvature", "ego_polar"]


def ego_polar(
    target: ArrayLike, current: ArrayLike = (0.0, 0.0, 0.0), backward: bool = False
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Egocentric polar coordinates of a target pose seen from the current pose.

    Parameters
    ----------
    target, current
        ``(..., 3)`` poses ``(x, y, yaw)`` in one frame, metres and radians.
    backward
        Flip the line of sight, for a robot that drives backwards to the target.

    Returns
    -------
    r, phi, delta
        ``(...)`` distance (metres), target orientation and robot heading with respect to the
        line of sight (radians, in ``[-pi, pi)``, measured clockwise as in nav2).
    """
    t = np.asarray(target, dtype=np.float64)
    c = np.asarray(current, dtype=np.float64)
    dx, dy = t[..., 0] - c[..., 0], t[..., 1] - c[..., 1]
    line_of_sight = np.arctan2(-dy, dx) + (math.pi if backward else 0.0)
    return (
        np.hypot(dx, dy),
        wrap_angle(t[..., 2] + line_of_sight),
        wrap_angle(c[..., 2] + line_of_sight),
    )


def curvature(
    r: ArrayLike, phi: ArrayLike, delta: ArrayLike, k_phi: float, k_delta: float
) -> NDArray[np.float64]:
    """Path curvature of the smooth control law, 1/metres (paper eq. 38, Park & Kuipers).

    Parameters
    ----------
    r
        Distance to the target, metres (> 0).
    phi, delta
        Target orientation and robot heading with respect to the line of sight, radians.
    k_phi, k_delta
        The gains (the paper's ``k1``, ``k2``: 4 and 12 in its simulations).

    Returns
    -------
    numpy.ndarray
        ``kappa = omega / v``, positive to the left.
    """
    r_ = np.asarray(r, dtype=np.float64)
    phi_ = np.asarray(phi, dtype=np.float64)
    delta_ = np.asarray(delta, dtype=np.float64)
    prop = k_delta * (delta_ - np.arctan(-k_phi * phi_))
    feedback = (1.0 + k_phi / (1.0 + (k_phi * phi_) ** 2)) * np.sin(delta_)
    return np.asarray(-(prop + feedback) / r_, dtype=np.float64)


@dataclass(frozen=True, kw_only=True)
class SmoothControlLaw:
    """Speeds from the smooth control law, with the limits a real robot needs.

    Attributes
    ----------
    k_phi, k_delta
        Gains of the curvature (paper: ``k1 = 4``, ``k2 = 12``).
    beta, lam
        Speed from curvature: ``v = v_max / (1 + beta |kappa|^lam)``.
    slowdown_radius
        Within this distance of the target (metres) the speed falls linearly to 0.
    v_min, v_max
        Linear speed bounds, m/s.
    omega_max
        Angular speed bound, rad/s (the linear speed is reduced with it: the curvature is kept).
    rotate_radius
        Within this distance of the target (metres) the robot stops translating and turns on
        the spot to the target's yaw, ``omega = k_rotate * (phi - delta)`` (clamped); 0 (the
        default) never does. The curvature grows as ``1 / r``, so near the target a final
        in-place rotation is the robust way to fix the heading.
    k_rotate
        Gain of the final rotation, 1/s.
    """

    k_phi: float = 4.0
    k_delta: float = 12.0
    beta: float = 0.4
    lam: float = 2.0
    slowdown_radius: float = 0.5
    v_min: float = 0.0
    v_max: float = 1.2
    omega_max: float = math.radians(300.0)
    rotate_radius: float = 0.0
    k_rotate: float = 1.0

    def __post_init__(self) -> None:
        for name in (
            "k_phi",
            "k_delta",
            "slowdown_radius",
            "v_max",
            "omega_max",
            "lam",
            "k_rotate",
        ):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be finite and positive, got {value!r}")
        if not (math.isfinite(self.beta) and self.beta >= 0):
            raise ValueError(f"beta must be >= 0, got {self.beta!r}")
        if not (math.isfinite(self.rotate_radius) and self.rotate_radius >= 0):
            raise ValueError(f"rotate_radius must be >= 0, got {self.rotate_radius!r}")
        if not (0.0 <= self.v_min <= self.v_max):
            raise ValueError(f"need 0 <= v_min <= v_max, got {self.v_min!r}, {self.v_max!r}")

    def velocity(
        self, r: float, phi: float, delta: float, backward: bool = False
    ) -> tuple[float, float]:
        """Linear and angular speed ``(v, omega)`` (m/s, rad/s) towards the target.

        Parameters
        ----------
        r, phi, delta
            Egocentric polar coordinates (:func:`ego_polar`), metres and radians.
        backward
            Drive backwards (``phi``, ``delta`` from ``ego_polar(..., backward=True)``).

        Returns
        -------
        tuple of float
            ``(v, omega)``; ``(0, 0)`` at the target (``r = 0``).
        """
        if r <= 0.0:
            return 0.0, 0.0
        if r < self.rotate_radius:  # final rotation: phi - delta is the target yaw minus ours
            turn = self.k_rotate * math.remainder(phi - delta, 2.0 * math.pi)
            return 0.0, min(max(turn, -self.omega_max), self.omega_max)
        kappa = float(curvature(r, phi, delta, self.k_phi, self.k_delta))
        kappa = -kappa if backward else kappa
        v = self.v_max / (1.0 + self.beta * abs(kappa) ** self.lam)
        v = min(self.v_max * r / self.slowdown_radius, v)
        v = min(max(v, self.v_min), self.v_max)
        v = -v if backward else v
        omega = kappa * v
        bounded = min(max(omega, -self.omega_max), self.omega_max)
        if kappa != 0.0:
            v = bounded / kappa
        return v, bounded
