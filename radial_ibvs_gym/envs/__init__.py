"""Gymnasium environments, registered on ``import radial_ibvs_gym``."""

from gymnasium.envs.registration import register

from radial_ibvs_gym.envs.parking import ParkingEnv

__all__ = ["ENV_IDS", "ParkingEnv", "register_envs"]

ENV_IDS = ("RadialIBVS/Parking-v0",)


def register_envs() -> None:
    """Register the environments with Gymnasium (idempotent)."""
    from gymnasium.envs.registration import registry

    if "RadialIBVS/Parking-v0" not in registry:
        register(
            id="RadialIBVS/Parking-v0",
            entry_point="radial_ibvs_gym.envs.parking:ParkingEnv",
            max_episode_steps=600,
        )
