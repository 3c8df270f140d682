"""One episode of a policy in a given scalar env (``render``, ``demo``, ``reproduce``)."""

from __future__ import annotations

import math
import time
from collections.abc import Mapping
from typing import Any

import gymnasium as gym
import numpy as np

from radial_ibvs_agents.rollouts.log import EpisodeLog

__all__ = ["run_episode"]


def _image(obs: Mapping[str, Any]) -> tuple[Any, Any, Any]:
    """Return the current points, their visibility and the goal points of an observation.

    ``Parking-v0`` has them as ``points``, ``visible`` and ``goal_points``; the goal-conditioned
    ``ParkingGoal-v1`` as ``achieved_goal``, the last third of ``observation`` and
    ``desired_goal`` (their first ``2M`` values: with ``goal_depths=True`` the depths follow).
    ``ParkingImage-v0``'s images carry no points: none are logged (empty arrays).
    """
    if not isinstance(obs, Mapping) or ("points" not in obs and "observation" not in obs):
        return np.zeros(0), np.zeros(0), np.zeros(0)
    if "points" in obs:
        return obs["points"], obs["visible"], obs["goal_points"]
    n = len(obs["observation"]) // 3
    return (
        obs["achieved_goal"][: 2 * n],
        obs["observation"][2 * n :],
        obs["desired_goal"][: 2 * n],
    )


def run_episode(
    policy: Any,
    env: gym.Env,
    *,
    seed: int = 0,
    options: dict[str, Any] | None = None,
    policy_name: str | None = None,
    max_steps: int | None = None,
    record_frames: bool = False,
) -> EpisodeLog:
    """Run ``policy`` in ``env`` for one episode (until termination or truncation).

    Parameters
    ----------
    policy
        Anything with SB3's ``predict(observation, state, episode_start, deterministic)``.
    env
        A ``RadialIBVS/Parking-v0`` env (or one with the same observation and ``info``), made
        with the policy's ``env_kwargs``.
    seed
        Reset seed.
    options
        Reset options (``start``, ``goal``, ``task``).
    policy_name
        Name recorded in the log (default: the policy's class name).
    max_steps
        A further cap on the number of steps, below the env's own truncation (``None``: only
        the env's; to run longer than the registration's 600 steps, pass
        ``max_episode_steps`` to ``gym.make``).
    record_frames
        Keep ``env.render()`` after the reset and after every step in ``EpisodeLog.frames``
        (the env must be made with ``render_mode="rgb_array"``).

    Returns
    -------
    EpisodeLog
        The trajectory and metrics.
    """
    if record_frames and env.render_mode != "rgb_array":
        raise ValueError(
            f"record_frames needs an env made with render_mode='rgb_array', got {env.render_mode!r}"
        )
    obs, info = env.reset(seed=seed, options=options)
    frames = [np.asarray(env.render())] if record_frames else []
    base = env.unwrapped
    image = _image(obs)
    poses, points, visible = [info["robot_pose"]], [image[0]], [image[1]]
    actions: list[np.ndarray] = []
    state, episode_start, compute = None, np.ones(1, dtype=bool), 0.0
    limit = math.inf if max_steps is None else max_steps
    terminated = False
    while len(actions) < limit:
        start = time.perf_counter()
        action, state = policy.predict(obs, state, episode_start, deterministic=True)
        compute += time.perf_counter() - start
        episode_start = np.zeros(1, dtype=bool)
        obs, _, terminated, truncated, info = env.step(action)
        poses.append(info["robot_pose"])
        actions.append(np.asarray(action, dtype=np.float64))
        image = _image(obs)
        points.append(image[0])
        visible.append(image[1])
        if record_frames:
            frames.append(np.asarray(env.render()))
        if terminated or truncated:
            break
    n = len(visible[-1])
    return EpisodeLog(
        policy=policy_name or type(policy).__name__,
        scenario=base.scenario.config.name if hasattr(base, "scenario") else "?",
        physics=getattr(base, "physics", "?"),
        task=None if info.get("task") is None else int(info["task"]),
        seed=seed,
        control_dt=float(getattr(base, "control_dt", float("nan"))),
        poses=np.array(poses, dtype=np.float64),
        actions=np.array(actions, dtype=np.float64).reshape(-1, 2),
        points=np.array(points, dtype=np.float64).reshape(len(points), n, 2),
        visible=np.array(visible).reshape(len(visible), n) > 0.5,
        goal_points=np.asarray(image[2], dtype=np.float64).reshape(n, 2),
        info=info,
        compute_s=compute,
        frames=frames,
        terminated=terminated,
        success_hold_steps=int(getattr(getattr(base, "config", None), "success_hold_steps", 1)),
    )
