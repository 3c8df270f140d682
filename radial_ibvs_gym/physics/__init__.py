"""The simulated robot and its world (no gymnasium import).

Backends share one interface (``reset(pose)``, ``step(command, dt) -> StepResult``):
``kinematic`` integrates the unicycle exactly. The pymunk backend (walls, obstacles, contact)
follows.
"""

from radial_ibvs_gym.physics.diffdrive import (
    RobotConfig,
    limit_command,
    twist_to_wheels,
    wheels_to_twist,
)
from radial_ibvs_gym.physics.kinematic import KinematicWorld, StepResult, integrate_unicycle

__all__ = [
    "KinematicWorld",
    "RobotConfig",
    "StepResult",
    "integrate_unicycle",
    "limit_command",
    "twist_to_wheels",
    "wheels_to_twist",
]
