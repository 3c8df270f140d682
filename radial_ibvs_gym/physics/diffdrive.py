"""The differential-drive robot: physical parameters, wheel kinematics and command limits.

Defaults follow a Pioneer 3-DX (455 x 381 mm body, 330 mm wheel base, 1.2 m/s, 300 deg/s).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from radial_ibvs_gym.limits import MAX_WORLD_M, MIN_ROBOT_M

#: the robot's dimensions (bounded by MIN_ROBOT_M and MAX_WORLD_M: pymunk needs a body)
_SIZES = ("length", "width", "wheel_base", "wheel_radius")

__all__ = [
    "RobotConfig",
    "limit_command",
    "limited_twist",
    "twist_to_wheels",
    "wheels_to_twist",
]


@dataclass(frozen=True, kw_only=True)
class RobotConfig:
    """Physical parameters of a differential-drive robot.

    Attributes
    ----------
    length, width
        Body footprint along and across the heading, metres.
    wheel_base
        Distance between the two drive wheels, metres.
    wheel_radius
        Drive wheel radius, metres.
    mass
        Body mass, kilograms (used by the pymunk backend).
    max_linear_speed
        ``|v|`` limit, m/s.
    max_angular_speed
        ``|omega|`` limit, rad/s.
    max_linear_accel, max_angular_accel
        Acceleration limits, m/s^2 and rad/s^2 (``inf``: none).
    saturation
        How speed limits apply: ``"scale"`` divides ``v`` and ``omega`` by one factor (the
        curvature ``omega / v``, hence the path, is kept); ``"clip"`` clips each separately.
    """

    length: float = 0.455
    width: float = 0.381
    wheel_base: float = 0.33
    wheel_radius: float = 0.0975
    mass: float = 9.0
    max_linear_speed: float = 1.2
    max_angular_speed: float = math.radians(300.0)
    max_linear_accel: float = 1.5
    max_angular_accel: float = math.radians(400.0)
    saturation: Literal["scale", "clip"] = "scale"

    def __post_init__(self) -> None:
        for f in fields(self):
            if f.name == "saturation":
                continue
            value = getattr(self, f.name)
            ok = isinstance(value, (int, float)) and not isinstance(value, bool) and value > 0
            may_be_inf = f.name.endswith("_accel")
            if not ok or (math.isinf(value) and not may_be_inf) or math.isnan(value):
                raise ValueError(f"robot {f.name} must be a positive number, got {value!r}")
            if f.name in _SIZES and not MIN_ROBOT_M <= value <= MAX_WORLD_M:
                raise ValueError(
                    f"robot {f.name} must be in [{MIN_ROBOT_M}, {MAX_WORLD_M:g}] m "
                    f"(MIN_ROBOT_M, MAX_WORLD_M), got {value!r}"
                )
        if self.saturation not in ("scale", "clip"):
            raise ValueError(f"saturation must be 'scale' or 'clip', got {self.saturation!r}")

    @classmethod
    def from_dict(cls, values: dict[str, Any]) -> RobotConfig:
        """Build from a mapping, rejecting unknown keys with the list of valid ones."""
        valid = {f.name for f in fields(cls)}
        unknown = sorted(set(values) - valid)
        if unknown:
            raise ValueError(f"unknown robot key(s) {unknown}; valid keys: {sorted(valid)}")
        return cls(**values)


def wheels_to_twist(wheel_speeds: ArrayLike, config: RobotConfig) -> NDArray[np.float64]:
    """Wheel angular speeds ``(..., 2)`` (left, right; rad/s) to ``(..., 2)`` ``(v, omega)``."""
    w = np.asarray(wheel_speeds, dtype=np.float64)
    left, right = config.wheel_radius * w[..., 0], config.wheel_radius * w[..., 1]
    return np.stack([(left + right) / 2.0, (right - left) / config.wheel_base], axis=-1)


def twist_to_wheels(twist: ArrayLike, config: RobotConfig) -> NDArray[np.float64]:
    """``(v, omega)`` ``(..., 2)`` (m/s, rad/s) to wheel speeds ``(..., 2)`` (left, right)."""
    t = np.asarray(twist, dtype=np.float64)
    half = 0.5 * config.wheel_base * t[..., 1]
    return np.stack([t[..., 0] - half, t[..., 0] + half], axis=-1) / config.wheel_radius


def limit_command(
    command: ArrayLike, previous: ArrayLike, dt: float, config: RobotConfig
) -> NDArray[np.float64]:
    """Apply the speed limits, then the acceleration limits, to a ``(v, omega)`` command.

    Parameters
    ----------
    command
        ``(2,)`` requested ``(v, omega)``, m/s and rad/s.
    previous
        ``(2,)`` the velocity applied over the previous control period.
    dt
        Control period, seconds (> 0).
    config
        The robot.

    Returns
    -------
    numpy.ndarray
        ``(2,)`` the velocity to apply.

    Raises
    ------
    ValueError
        If the command is NaN or infinite.
    """
    v0, w0 = np.asarray(previous, dtype=np.float64).tolist()
    return np.array(limited_twist(command, (v0, w0), dt, config))


def limited_twist(
    command: ArrayLike, previous: tuple[float, float], dt: float, config: RobotConfig
) -> tuple[float, float]:
    """:func:`limit_command` on Python floats: the same limits, the same numbers.

    Parameters
    ----------
    command
        ``(2,)`` requested ``(v, omega)``, m/s and rad/s (a tuple of two floats is read as is).
    previous
        The ``(v, omega)`` applied over the previous control period, as two floats.
    dt
        Control period, seconds (> 0).
    config
        The robot.

    Returns
    -------
    tuple of float
        The ``(v, omega)`` to apply, m/s and rad/s.

    Raises
    ------
    ValueError
        If the command is NaN or infinite.
    """
    if type(command) is tuple and len(command) == 2:  # the envs' fast path: two floats
        v, w = float(command[0]), float(command[1])
    else:
        cmd = np.asarray(command, dtype=np.float64)
        if cmd.shape != (2,):
            raise ValueError(f"command must be two finite numbers (v, omega), got {command!r}")
        v, w = cmd.tolist()
    if not (math.isfinite(v) and math.isfinite(w)):
        raise ValueError(f"command must be two finite numbers (v, omega), got {command!r}")
    v_max, w_max = config.max_linear_speed, config.max_angular_speed
    if config.saturation == "scale":
        factor = max(1.0, abs(v) / v_max, abs(w) / w_max)
        v, w = v / factor, w / factor
    else:
        v, w = min(max(v, -v_max), v_max), min(max(w, -w_max), w_max)
    v0, w0 = previous
    dv, dw = dt * config.max_linear_accel, dt * config.max_angular_accel
    return min(max(v, v0 - dv), v0 + dv), min(max(w, w0 - dw), w0 + dw)
