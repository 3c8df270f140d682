"""The simulated robot and its world (no gymnasium import).

Backends share one interface (``reset(pose)``, ``step(command, dt) -> StepResult``, ``pose``,
``velocity``, ``time``): ``pymunk`` simulates a rigid body with contacts against the walls,
``kinematic`` integrates the unicycle exactly (the paper's simulations are kinematic). Their
fleets (:mod:`.fleet`) step ``N`` robots, each in its own room, at once.
"""

from typing import Any

from radial_ibvs_gym.physics.base import StepResult, World
from radial_ibvs_gym.physics.diffdrive import (
    RobotConfig,
    limit_command,
    limited_twist,
    twist_to_wheels,
    wheels_to_twist,
)
from radial_ibvs_gym.physics.fleet import Fleet, KinematicFleet, PymunkFleet, make_fleet
from radial_ibvs_gym.physics.kinematic import KinematicWorld, integrate_unicycle
from radial_ibvs_gym.physics.pymunk_world import PymunkWorld

BACKENDS = ("pymunk", "kinematic")


def make_world(backend: str, robot: RobotConfig, room: tuple[float, float], **kwargs: Any) -> World:
    """Build a world of the named backend (``"pymunk"`` or ``"kinematic"``).

    Raises
    ------
    ValueError
        For an unknown backend (the message lists the valid ones).
    """
    if backend == "pymunk":
        return PymunkWorld(robot, room, **kwargs)
    if backend == "kinematic":
        return KinematicWorld(robot, room, **kwargs)
    raise ValueError(f"unknown physics {backend!r}; valid: {list(BACKENDS)}")


__all__ = [
    "BACKENDS",
    "Fleet",
    "KinematicFleet",
    "KinematicWorld",
    "PymunkFleet",
    "PymunkWorld",
    "RobotConfig",
    "StepResult",
    "World",
    "integrate_unicycle",
    "limit_command",
    "limited_twist",
    "make_fleet",
    "make_world",
    "twist_to_wheels",
    "wheels_to_twist",
]
