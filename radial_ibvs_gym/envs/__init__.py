"""Gymnasium environments, registered on ``import radial_ibvs_gym``."""

from gymnasium.envs.registration import register

from radial_ibvs_gym.envs.parking import ParkingEnv
from radial_ibvs_gym.envs.parking_goal import ParkingGoalEnv
from radial_ibvs_gym.envs.parking_image import ParkingImageEnv

__all__ = ["ENV_IDS", "ParkingEnv", "ParkingGoalEnv", "ParkingImageEnv", "register_envs"]

#: every registered id, with its entry point
ENTRY_POINTS = {
    "RadialIBVS/Parking-v0": "radial_ibvs_gym.envs.parking:ParkingEnv",
    "RadialIBVS/ParkingGoal-v0": "radial_ibvs_gym.envs.parking_goal:ParkingGoalEnv",
    "RadialIBVS/ParkingImage-v0": "radial_ibvs_gym.envs.parking_image:ParkingImageEnv",
}
ENV_IDS = tuple(ENTRY_POINTS)


def register_envs() -> None:
    """Register the environments with Gymnasium (idempotent)."""
    from gymnasium.envs.registration import registry

    for env_id, entry_point in ENTRY_POINTS.items():
        if env_id not in registry:
            register(id=env_id, entry_point=entry_point, max_episode_steps=600)
