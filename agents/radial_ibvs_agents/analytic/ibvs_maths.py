"""The paper's IBVS for a planar robot (Section 3.3, eq. 30-37), as pure maths.

Only the goal interaction matrix is used (its pseudo-inverse computed once per goal) and the
tensor change of frame is approximated by the rotation ``gamma`` estimated from ``alpha_m``.

Sign conventions fixed here (camera twist ``(v, omega)``, ``dP/dt = -v - omega x P``):

- eq. (30), translation: ``v* = -lambda L*+ (s* - s)`` is the velocity that moves the *goal*
  camera towards the current one; to first order ``v* = lambda t`` with ``t`` the current
  camera position in the goal frame.
- eq. (30), rotation: ``alpha_m`` of the current image is ``alpha_m* + L*_alpha_m,v . t - theta``
  (``theta``: current yaw minus goal yaw), so ``omega*_z = lambda (alpha*_m - alpha_m)
  + L*_alpha_m,v . v*`` recovers ``lambda theta``. The paper prints ``-`` before the
  compensation terms (``docs/notes-controller.md``, misprint 1); with it ``gamma`` is wrong
  by ``O(r / d)``.
- ``omega_z = -omega*_z`` and ``gamma = omega_z / lambda`` (eq. 37) is then the rotation from
  the current to the goal orientation, ``-theta``.
- eq. (36)-(37): ``(v_x, v_y) = -R(gamma) v*``, the velocity that moves the current camera
  towards the goal, in the current frame.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from radial_ibvs_gym.features import L_alpha_m, L_cij, alpha_m, c_ij, virtual_point_weights
from radial_ibvs_gym.geometry import rot2, wrap_angle_scalar

__all__ = ["GoalModel", "ibvs_twist", "park_command", "robot_command"]


@dataclass(frozen=True)
class GoalModel:
    """What the paper's IBVS precomputes from the goal image and the goal depths ``d*``.

    Attributes
    ----------
    x_n_goal
        ``(N, 2)`` goal image points on the unit circle.
    c_goal
        ``(M,)`` goal features ``c*_ij`` (eq. 12).
    weights
        ``(N,)`` virtual-point weights ``a`` (eq. 27-29), so ``alpha*_m = 0``.
    L_c_v
        ``(M, 2)`` the ``(v_x, v_y)`` columns of ``L*_c`` (eq. 17).
    L_c_pinv
        ``(2, M)`` their pseudo-inverse.
    L_alpha_m_v
        ``(2,)`` the ``(v_x, v_y)`` entries of ``L*_alpha_m`` (eq. 24, 26).
    """

    x_n_goal: NDArray[np.float64]
    c_goal: NDArray[np.float64]
    weights: NDArray[np.float64]
    L_c_v: NDArray[np.float64]
    L_c_pinv: NDArray[np.float64]
    L_alpha_m_v: NDArray[np.float64]

    @classmethod
    def from_goal(cls, x_n_goal: NDArray[np.float64], d_goal: NDArray[np.float64]) -> GoalModel:
        """Precompute the goal model (once per goal).

        Parameters
        ----------
        x_n_goal
            ``(N, 2)`` goal image points, ``N >= 3``.
        d_goal
            ``(N,)`` goal depths ``d*`` (horizontal distances, metres), possibly scaled.
        """
        x = np.asarray(x_n_goal, dtype=np.float64)
        d = np.asarray(d_goal, dtype=np.float64)
        z = np.zeros_like(d)  # Z only enters the omega_x, omega_y columns, unused on a plane
        a = virtual_point_weights(x)
        L_c = L_cij(x, d, z)[:, :2]
        return cls(
            x_n_goal=x,
            c_goal=c_ij(x),
            weights=a,
            L_c_v=L_c,
            L_c_pinv=np.asarray(np.linalg.pinv(L_c), dtype=np.float64),
            L_alpha_m_v=L_alpha_m(x, d, z, a)[:2],
        )


def ibvs_twist(
    x_n: NDArray[np.float64],
    goal: GoalModel,
    lam: float = 1.0,
    compensation: Literal["derived", "printed"] = "derived",
) -> tuple[NDArray[np.float64], float, float]:
    """Camera velocity of the paper's IBVS in the current frame (eq. 30, 36-37).

    Parameters
    ----------
    x_n
        ``(N, 2)`` current image points, in the goal's order.
    goal
        The goal model.
    lam
        The gain ``lambda`` (1/s).
    compensation
        ``"derived"``: the sign of eq. (30)'s compensation terms derived above;
        ``"printed"``: the paper's printed sign (for comparison only).

    Returns
    -------
    v
        ``(2,)`` translational velocity ``(v_x, v_y)`` in the current camera frame, m/s.
    omega_z
        Angular velocity ``omega_z = -omega*_z``, rad/s.
    gamma
        Estimated rotation from the current to the goal orientation, radians (eq. 37).
    """
    s = c_ij(x_n)
    v_star = -lam * goal.L_c_pinv @ (goal.c_goal - s)
    error_alpha = wrap_angle_scalar(-float(alpha_m(x_n, goal.weights)))  # alpha*_m = 0
    sign = 1.0 if compensation == "derived" else -1.0
    omega_star = lam * error_alpha + sign * float(goal.L_alpha_m_v @ v_star)
    omega_z = -omega_star
    gamma = omega_z / lam
    v = -(rot2(gamma) @ v_star)
    return v, omega_z, gamma


def robot_command(
    v: NDArray[np.float64],
    gamma: float,
    lam: float,
    k1: float = 4.0,
    k2: float = 12.0,
    v_max: float = 1.2,
    omega_max: float = 5.235987755982989,
    allow_backward: bool = False,
) -> tuple[float, float]:
    """Robot speeds ``(v_l, omega)`` from the IBVS camera velocity, through eq. (38).

    The camera velocity defines a virtual target in the robot frame: distance
    ``r = |v| / lambda``, direction ``delta = atan2(v_y, v_x)``, orientation ``gamma`` relative
    to the robot (Section 4: ``v_l / r = lambda``). The smooth control law's curvature towards
    that target (nav2's conventions, :mod:`radial_ibvs_agents.analytic.smooth_control`) gives
    ``omega = kappa v_l`` with ``v_l = |v|``; speed limits scale ``v_l`` and ``omega``
    together, keeping the curvature (so the path does not depend on them).

    Parameters
    ----------
    v
        ``(2,)`` camera velocity in the current frame, m/s (camera on the robot's axis).
    gamma
        Estimated rotation to the goal orientation, radians.
    lam
        The IBVS gain, 1/s.
    k1, k2
        Gains of eq. (38) (the paper's simulations: 4 and 12).
    v_max, omega_max
        Speed limits, m/s and rad/s.
    allow_backward
        Drive backwards when the virtual target is behind the robot (``v_x < 0``), as nav2's
        graceful controller does with ``allow_backward``: the law of eq. (38) with the line of sight
        flipped (:func:`~radial_ibvs_agents.analytic.smooth_control.ego_polar` ``backward=True``)
        and a negative ``v_l``. Off (forward only, the paper's law) by default.

    Returns
    -------
    tuple of float
        ``(v_l, omega)``; zero when ``|v|`` vanishes.
    """
    from radial_ibvs_agents.analytic.smooth_control import curvature, ego_polar

    v_l = float(np.hypot(v[0], v[1]))
    if v_l <= 1e-12:
        return 0.0, 0.0
    r = v_l / lam
    delta = float(np.arctan2(v[1], v[0]))
    target = (r * np.cos(delta), r * np.sin(delta), gamma)
    reverse = allow_backward and target[0] < 0.0  # the target is behind the robot
    kappa = float(curvature(*ego_polar(target, backward=reverse), k1, k2))
    if reverse:  # the law of SmoothControlLaw.velocity(..., backward=True)
        kappa, v_l = -kappa, -v_l
    omega = kappa * v_l
    factor = max(1.0, abs(v_l) / v_max, abs(omega) / omega_max)
    return v_l / factor, omega / factor


def park_command(
    v: NDArray[np.float64],
    gamma: float,
    lam: float,
    k1: float,
    k2: float,
    v_max: float,
    omega_max: float,
    stop_radius: float,
    stop_heading: float,
    rotate_radius: float,
    allow_backward: bool = False,
) -> tuple[float, float]:
    """:func:`robot_command` with the stop rule and the final rotation around it.

    Eq. (38) is singular at the goal: as ``r -> 0`` the curvature grows as ``1 / r`` and its
    sign follows the (then meaningless) direction of ``v``. So, with ``r = |v| / lam``:

    - ``r < stop_radius`` and ``|gamma| < stop_heading``: zero command (the stop rule);
    - ``r < rotate_radius``: the final approach, ``v_l = v_x`` (the forward part of ``v``,
      forwards or backwards) and ``omega = lam gamma`` (clamped): the heading is servoed on
      ``gamma`` (from ``alpha_m``, robust to image noise) instead of the direction of ``v``,
      which image noise dominates near the goal;
    - otherwise eq. (38) (:func:`robot_command`).

    Parameters
    ----------
    v, gamma, lam, k1, k2, v_max, omega_max
        As in :func:`robot_command` (m/s, radians, 1/s, rad/s).
    stop_radius, rotate_radius
        Metres.
    stop_heading
        Radians.
    allow_backward
        As in :func:`robot_command`.

    Returns
    -------
    tuple of float
        ``(v_l, omega)``, m/s and rad/s.
    """
    r = float(np.hypot(v[0], v[1])) / lam
    if r < stop_radius and abs(gamma) < stop_heading:
        return 0.0, 0.0
    if r < rotate_radius:  # final approach: the forward part of v, and turn to the goal heading
        return float(v[0]), min(max(lam * gamma, -omega_max), omega_max)
    return robot_command(v, gamma, lam, k1, k2, v_max, omega_max, allow_backward)
