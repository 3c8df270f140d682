"""Reference and learned policies for the radial IBVS parking tasks.

Every policy implements stable-baselines3's ``predict(observation, state=None,
episode_start=None, deterministic=True) -> (action, state)`` and says, in ``env_kwargs``, what
``gym.make`` must add to the observation for it. :func:`make_policy` builds them by name;
:func:`load` loads a trained model (shipped or from ``radial-ibvs train``);
:func:`make_vec_env` makes a stable-baselines3 ``VecEnv`` backed by the native batched env
(imported on first use: it loads stable-baselines3 and torch).
"""

from typing import Any

from radial_ibvs_agents.analytic import (
    VARIANTS,
    IBVSPolicy,
    PoseOracle,
    SmoothControlLaw,
    curvature,
    ego_polar,
)
from radial_ibvs_agents.learned import LearnedPolicy, load, shipped_models
from radial_ibvs_agents.registry import POLICY_NAMES, Policy, RandomPolicy, make_policy

__all__ = [
    "POLICY_NAMES",
    "VARIANTS",
    "IBVSPolicy",
    "LearnedPolicy",
    "Policy",
    "PoseOracle",
    "RandomPolicy",
    "SmoothControlLaw",
    "curvature",
    "ego_polar",
    "load",
    "make_policy",
    "make_vec_env",
    "save_model_dir",
    "shipped_models",
]


def __getattr__(name: str) -> Any:
    """Import :func:`make_vec_env` and ``save_model_dir`` on first use (they load SB3, torch)."""
    if name == "make_vec_env":
        from radial_ibvs_agents.learned.training.sb3_vec_env import make_vec_env

        return make_vec_env
    if name == "save_model_dir":
        from radial_ibvs_agents.learned.files.saving import save_model_dir

        return save_model_dir
    raise AttributeError(f"module 'agents' has no attribute {name!r}")
