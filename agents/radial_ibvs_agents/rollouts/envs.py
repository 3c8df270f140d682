"""The env a policy runs in: the ``gym.make`` keywords merged in one order, and the fit checked."""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any

import gymnasium as gym

from radial_ibvs_gym.registration import check_env_id
from radial_ibvs_gym.scenarios import ScenarioConfig

__all__ = ["DEFAULT_ENV_ID", "env_id_for", "env_kwargs_for", "make_env"]

#: the env every command runs unless told otherwise
DEFAULT_ENV_ID = "RadialIBVS/Parking-v0"

#: a policy's keywords that describe the world it was trained in, not how it observes: the
#: scenario's keys (room, landmarks, camera, mirrors, camera height...), the task, the start
#: curriculum, the goal image's frames and missed detections. A named scenario replaces them.
WORLD_KEYS = frozenset(
    {f.name for f in dataclasses.fields(ScenarioConfig)}
    | {"task", "start_reach", "goal_image_frames", "missed_detections"}
)


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
        ``{**policy.env_kwargs, "scenario": scenario, **overrides}``; with a ``scenario``, the
        policy's :data:`WORLD_KEYS` are left out: a model trained with its cameras or scenes
        drawn from ranges (domain randomisation) is judged in the scenario named, not in its
        training world.
    """
    kwargs: dict[str, Any] = dict(getattr(policy, "env_kwargs", {}))
    if scenario is not None:
        kwargs = {k: v for k, v in kwargs.items() if k not in WORLD_KEYS}
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
