"""Gymnasium environments, registered on ``import radial_ibvs_gym`` (by entry-point strings)."""

from radial_ibvs_gym.envs.parking import ParkingEnv
from radial_ibvs_gym.envs.parking_goal import ParkingGoalEnv, ParkingGoalEnvV1
from radial_ibvs_gym.envs.parking_image import ParkingImageEnv
from radial_ibvs_gym.registration import ENTRY_POINTS, ENV_IDS, register_envs

__all__ = [
    "ENTRY_POINTS",
    "ENV_IDS",
    "ParkingEnv",
    "ParkingGoalEnv",
    "ParkingGoalEnvV1",
    "ParkingImageEnv",
    "register_envs",
]
