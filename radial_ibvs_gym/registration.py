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
    "UnknownEnvIdError",
    "check_env_id",
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


class UnknownEnvIdError(ValueError):
    """An env id that is not one of this package's (:data:`ENV_IDS`)."""


def check_env_id(env_id: object, where: str = "env_id") -> str:
    """Return ``env_id`` if it is one of :data:`ENV_IDS`, else raise naming ``where``.

    An id read from a file (a model's ``metadata.json``, a training config's section name)
    goes through here before ``gym.make``: Gymnasium reads ``"module:EnvId"`` as "import
    ``module`` first", which would run code named by the file.

    Parameters
    ----------
    env_id
        The id to check, e.g. ``"RadialIBVS/Parking-v0"``.
    where
        What holds it, for the message (a file and key, e.g. ``"model/metadata.json: env_id"``).

    Raises
    ------
    UnknownEnvIdError
        For anything else (a ``ValueError``); the message names ``where``, the value and the
        valid ids.
    """
    if isinstance(env_id, str) and env_id in ENTRY_POINTS:
        return env_id
    text = repr(env_id)
    text = text if len(text) <= 120 else text[:117] + "..."
    why = (
        " (the 'module:' form imports a module, so it is never taken from a file or option)"
        if isinstance(env_id, str) and ":" in env_id
        else ""
    )
    raise UnknownEnvIdError(
        f"{where}: {text} is not an env of radial_ibvs_gym{why}; valid: {list(ENV_IDS)}"
    )


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
