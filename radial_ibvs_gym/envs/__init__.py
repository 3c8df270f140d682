"""Gymnasium environments, registered on ``import radial_ibvs_gym`` (by entry-point strings)."""

from radial_ibvs_gym.envs.config import ParkingConfig, UnknownArgumentError
from radial_ibvs_gym.envs.parking import ParkingEnv
from radial_ibvs_gym.envs.parking_goal import ParkingGoalEnv
from radial_ibvs_gym.envs.parking_image import ParkingImageEnv
from radial_ibvs_gym.registration import ENTRY_POINTS, ENV_IDS, register_envs

__all__ = [
    "ENTRY_POINTS",
    "ENV_IDS",
    "ParkingConfig",
    "ParkingEnv",
    "ParkingGoalEnv",
    "ParkingImageEnv",
    "UnknownArgumentError",
    "register_envs",
]
