"""The env a policy runs in: the ``gym.make`` keywords merged in one order, and the fit checked."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import gymnasium as gym

from radial_ibvs_gym.registration import check_env_id

__all__ = ["DEFAULT_ENV_ID", "env_id_for", "env_kwargs_for", "make_env"]

#: the env every command runs unless told otherwise
DEFAULT_ENV_ID = "RadialIBVS/Parking-v0"


def env_id_for(policy: Any, env_id: str | None = None) -> str:
    """Return the checked Gymnasium id to run ``policy`` in.

    ``env_id`` when given, else the policy's ``env_id`` (a learned model's training env), else
    :data:`DEFAULT_ENV_ID`.
    """
    given = env_id or getattr(policy, "env_id", None) or DEFAULT_ENV_ID
    return check_env_id(given, "env_id" if env_id else f"{policy!r}: env_id")


def env_kwargs_for(
    policy: Any, scenario: str | None = None, overrides: Mapping[str, Any] | None = None
) -> dict[str, Any]:
    """Merge the ``gym.make`` keywords for a policy, in the one order every command uses.

    Parameters
    ----------
    policy
        A policy with an ``env_kwargs`` mapping (every policy of :mod:`agents`; none: ``{}``).
    scenario
        Scenario name or YAML path; ``None`` keeps the policy's (or the env's default).
    overrides
        The caller's ``gym.make`` keywords; they win over the policy's.

    Returns
    -------
    dict
        ``{**policy.env_kwargs, "scenario": scenario, **overrides}``.
    """
    kwargs: dict[str, Any] = dict(getattr(policy, "env_kwargs", {}))
    if scenario is not None:
        kwargs["scenario"] = scenario
    kwargs.update(overrides or {})
    return kwargs


def make_env(
    policy: Any,
    scenario: str | None = None,
    overrides: Mapping[str, Any] | None = None,
    *,
    env_id: str | None = None,
    **make_kwargs: Any,
) -> gym.Env:
    """Make the env ``policy`` needs (:func:`env_kwargs_for`) and check that the policy fits it.

    Parameters
    ----------
    policy, scenario, overrides
        As :func:`env_kwargs_for`.
    env_id
        The Gymnasium id; default: the policy's ``env_id`` (a learned model's training env),
        else :data:`DEFAULT_ENV_ID`.
    **make_kwargs
        ``gym.make`` keywords that are not env settings (``render_mode``,
        ``max_episode_steps``).

    Raises
    ------
    ValueError
        For a bad keyword, or a learned model whose observation space differs from the env's
        (the env is closed first).
    """
    env = gym.make(
        env_id_for(policy, env_id), **make_kwargs, **env_kwargs_for(policy, scenario, overrides)
    )
    if hasattr(policy, "check_observation_space"):
        try:
            policy.check_observation_space(env.observation_space)
        except ValueError:
            env.close()
            raise
    return env
