"""A line-following docking law for a differential-drive robot: the teacher's last metres.

Near the goal, in the goal's frame (``x`` along the goal heading, ``y`` to its left, ``phi``
the robot's heading minus the goal heading), the robot drives to the goal's foot on its own
heading line and steers onto the goal's heading line::

    v     = sign(a) * ramp(|a|),            a = -(x cos(phi) + y sin(phi))
    omega = -k_y * v * y - 2 sqrt(k_y) * |v| * phi - sign(phi) * ramp(|phi|)

(``ramp`` is the proportional speed limited by the robot's speed and deceleration). The first
two terms steer onto the goal heading line: linearised about it (``y' = v phi``,
``phi' = omega``) and in the distance ``s`` travelled, ``y'' + 2 sqrt(k_y) y' + k_y y = 0``
(critically damped, the offset decaying over ``1 / sqrt(k_y)`` metres) for either sign of
``v``, so the law also backs up onto the goal after an overshoot. The last term turns to the
goal heading where the speed has faded. Both commands are smooth functions of the pose, and
near the goal the turn is dominated by the heading error (the lateral term is a product of
two small offsets), which an image resolves well, unlike the bearing to a goal a few
centimetres away.

This is the classic line-tracking law of unicycle control (after Samson; see Canudas de Wit,
Siciliano and Bastin, *Theory of Robot Control*, Springer, 1996), not the paper's: the
paper's smooth law is :mod:`radial_ibvs_agents.analytic.smooth_control`.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from radial_ibvs_gym.geometry import pose_in_frame

__all__ = ["goal_frame", "in_docking_cone", "line_docking", "ramp", "turn_in_place"]

F64 = NDArray[np.float64]


def ramp(distance: float, limit: float, accel: float, gain: float) -> float:
    """Return the speed that stops on ``distance``: proportional, limited, ramped down.

    Parameters
    ----------
    distance
        What is left to cover, metres or radians (``>= 0``).
    limit, accel
        The speed and acceleration limits, per second and per second squared.
    gain
        The proportional gain, 1/s.
    """
    return min(limit, gain * distance, math.sqrt(2.0 * accel * distance))


def goal_frame(pose: F64, goal: F64) -> tuple[float, float, float]:
    """Return the robot's pose in the goal's frame.

    Parameters
    ----------
    pose, goal
        ``(x, y, yaw)`` in the world frame, metres and radians, shape ``(3,)``.

    Returns
    -------
    tuple of float
        ``(x_g, y_g, phi)``: the position along and to the left of the goal heading, metres,
        and the heading minus the goal heading wrapped to ``[-pi, pi)``, radians.
    """
    return pose_in_frame(goal, pose)


def in_docking_cone(x_g: float, y_g: float, cone: float, band: float) -> bool:
    """Whether a position lies where :func:`line_docking` parks.

    That is behind the goal within ``cone`` radians of its heading line, or within ``band``
    metres of that line on either side of the goal (the law then backs up or drives on to it
    with a lateral offset below ``band``).

    Parameters
    ----------
    x_g, y_g
        Position in the goal's frame (:func:`goal_frame`), metres.
    cone
        Half-angle of the cone behind the goal, radians, in ``[0, pi/2)``.
    band
        Half-width of the band around the goal heading line, metres.
    """
    return abs(y_g) <= max(math.tan(cone) * max(-x_g, 0.0), band)


def line_docking(
    x_g: float,
    y_g: float,
    phi: float,
    *,
    gain: float,
    lateral_gain: float,
    max_speed: float,
    max_accel: float,
    max_turn: float,
    max_turn_accel: float,
) -> tuple[float, float]:
    """Return the docking command ``(v, omega)`` in metres per second and radians per second.

    Parameters
    ----------
    x_g, y_g, phi
        The robot's pose in the goal's frame (:func:`goal_frame`), metres and radians.
    gain
        Proportional gain of the drive and the turn, 1/s.
    lateral_gain
        ``k_y``, the turn per unit of speed and lateral offset, rad/m^2; the offset decays
        over ``1 / sqrt(k_y)`` metres of travel.
    max_speed, max_accel
        The robot's linear speed and acceleration limits, m/s and m/s^2.
    max_turn, max_turn_accel
        The robot's angular speed and acceleration limits, rad/s and rad/s^2.
    """
    along = -(x_g * math.cos(phi) + y_g * math.sin(phi))  # the goal's foot on the heading line
    v = math.copysign(ramp(abs(along), max_speed, max_accel, gain), along)
    steer = -lateral_gain * v * y_g - 2.0 * math.sqrt(lateral_gain) * abs(v) * phi
    omega = steer - math.copysign(ramp(abs(phi), max_turn, max_turn_accel, gain), phi)
    return v, float(np.clip(omega, -max_turn, max_turn))


def turn_in_place(
    phi: float, *, gain: float, max_turn: float, max_turn_accel: float, floor: float = 0.0
) -> float:
    """Return the turn rate that brings the heading error ``phi`` to zero in place, rad/s.

    ``omega = -sign(phi) * max(min(floor, max_turn), min(max_turn, gain * |phi|,
    sqrt(2 * max_turn_accel * |phi|)))`` for ``phi != 0``, and 0 at ``phi = 0``; the speed is
    zero, so the position stays where it is (the pose is the wheel axle's midpoint). Within
    the success radius this is the shortest way to park, and its command depends on the
    heading error alone, which an image resolves well.

    Parameters
    ----------
    phi
        The heading minus the goal heading (:func:`goal_frame`), radians.
    gain
        Proportional gain, 1/s (keep it below ``1 / control_dt`` for a monotone approach).
    max_turn, max_turn_accel
        The robot's angular speed and acceleration limits, rad/s and rad/s^2.
    floor
        The least turn rate while ``phi != 0``, rad/s (default 0: none). The proportional
        turn fades with the error, and a learned policy that fits it to within a few hundredths
        of the turn range stops a few degrees short; with a floor, the last degrees' turn stays
        that large. A step of ``control_dt`` seconds then overshoots by at most
        ``floor * control_dt`` radians: keep that under twice the heading tolerance, so that
        the step lands within the tolerance rather than across it.
    """
    if phi == 0.0:
        return 0.0
    size = max(min(floor, max_turn), ramp(abs(phi), max_turn, max_turn_accel, gain))
    return -math.copysign(size, phi)
