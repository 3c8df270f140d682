"""The environment ids and their entry points, registered with Gymnasium by strings.

Gymnasium imports an env's module only when the env is made, so registering costs nothing:
this module imports neither the env classes nor the simulator, and Gymnasium itself only
inside :func:`register_envs`.
"""

from __future__ import annotations

__all__ = [
    "ENTRY_POINTS",
    "ENV_IDS",
    "MAX_EPISODE_STEPS",
    "VECTOR_ENTRY_POINTS",
    "register_envs",
]

#: every registered id, with the entry point of its scalar env
ENTRY_POINTS: dict[str, str] = {
    "RadialIBVS/Parking-v0": "radial_ibvs_gym.envs.parking:ParkingEnv",
    "RadialIBVS/ParkingGoal-v1": "radial_ibvs_gym.envs.parking_goal:ParkingGoalEnv",
    "RadialIBVS/ParkingImage-v0": "radial_ibvs_gym.envs.parking_image:ParkingImageEnv",
}
#: the ids with a native batched vector env (``gym.make_vec(..., "vector_entry_point")``)
VECTOR_ENTRY_POINTS: dict[str, str] = {
    "RadialIBVS/Parking-v0": "radial_ibvs_gym.envs.parking_vector:ParkingVectorEnv",
    "RadialIBVS/ParkingGoal-v1": "radial_ibvs_gym.envs.parking_goal:ParkingGoalVectorEnv",
}
ENV_IDS: tuple[str, ...] = tuple(ENTRY_POINTS)
#: the time limit of every registration: 600 control steps (60 s at ``control_dt = 0.1`` s)
MAX_EPISODE_STEPS = 600


def register_envs() -> None:
    """Register the environments with Gymnasium (idempotent)."""
    from gymnasium.envs.registration import register, registry

    for env_id, entry_point in ENTRY_POINTS.items():
        if env_id not in registry:
            register(
                id=env_id,
                entry_point=entry_point,
                vector_entry_point=VECTOR_ENTRY_POINTS.get(env_id),
                max_episode_steps=MAX_EPISODE_STEPS,
            )
