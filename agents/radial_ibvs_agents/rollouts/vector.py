"""Many seeded episodes at once: the native vector env, one policy call per step for the batch.

:func:`run_batch` gives, for a list of seeds, the
:class:`~radial_ibvs_agents.rollouts.log.EpisodeLog` that
:func:`~radial_ibvs_agents.rollouts.run_episode` gives for each seed alone, with every episode
stepped in one ``gym.make_vec`` env (``autoreset_mode="disabled"``: an episode that ends leaves the
batch, no other seed takes its place). The episodes are the same, seed for seed: the native vector
env draws each robot's episode from its own generator, as the scalar env does.

The policy is called once per step on the robots whose episodes go on (its ``batch_mode``: the
analytic policies give each robot's action bit for bit as alone; the networks to the last bits
of a matrix product), or once per robot (the planner). A policy that keeps a state between
steps cuts it to those robots with its ``select_state(state, rows)``; one without that method
is called on the whole batch. The rows are the scalar runner's: bit for bit for the analytic
policies, through an ideal camera or one with imperfections (the vector env projects every
robot's landmarks in one batched root-find, which gives each point the bits it gets alone);
for the networks, whose actions differ in the last bits of a batched matrix product, the same
successes and ends through an ideal camera (the ideal-camera variants of the generalisation
suites, 408 episodes per policy), while through a noisy camera 1 to 16 of 100 episodes ended
the other way (both ways: the student's rate moved from 63 to 65 % through noise and
calibration error together), as small differences grow along a noisy episode. With
``measurement="detected"`` each robot's frame is rendered and detected one at a time inside
the vector env (on the kinematic backend, the only one batched here, the same points as the
scalar env's, bit for bit); the batch's policy call and step are batched around them. Where the
vector env cannot run a variant, :func:`batchable` says why, and
:func:`~radial_ibvs_agents.rollouts.run_episodes` runs the scalar path:

- ``physics="pymunk"``: the batched fleet shares one ``pymunk.Space``, whose solver orders
  contacts differently, so the rows would not be the scalar env's bit for bit;
- ``RadialIBVS/ParkingImage-v0`` has no vector env (it renders an image per robot).
"""

from __future__ import annotations

import time
from collections.abc import Mapping, Sequence
from typing import Any

import gymnasium as gym
import numpy as np

from radial_ibvs_agents.rollouts.log import EpisodeLog
from radial_ibvs_gym.registration import VECTOR_ENTRY_POINTS

__all__ = ["batchable", "run_batch"]


def batchable(env_id: str, env_kwargs: Mapping[str, Any]) -> str | None:
    """Return why the vector env cannot run these episodes as the scalar env would, or None."""
    if env_id not in VECTOR_ENTRY_POINTS:
        return f"{env_id} has no vector env"
    if env_kwargs.get("physics", "pymunk") == "pymunk":
        return "pymunk's batched contacts differ from the scalar env's in the last bits"
    return None


#: :func:`_state_of`'s answer for a state it cannot cut: call the policy on the whole batch
_WHOLE_BATCH = object()


def _state_of(policy: Any, state: Any, rows: np.ndarray) -> Any:
    """Return the policy's state for the robots at positions ``rows`` of its batch.

    ``None`` (no state) stays ``None``; a policy with a state cuts it by its
    ``select_state(state, rows)``; without that method the policy sees the whole batch.
    """
    if state is None:
        return None
    select = getattr(policy, "select_state", None)
    return _WHOLE_BATCH if select is None else select(state, rows)


def _row_of(values: Mapping[str, Any], i: int) -> dict[str, Any]:
    """Robot ``i``'s entries of a vector env's ``info`` (masks dropped), as the scalar env's."""
    out: dict[str, Any] = {}
    for key, value in values.items():
        if key.startswith("_"):
            continue
        if isinstance(value, Mapping):
            out[key] = _row_of(value, i)
        elif value.dtype == np.bool_ and value.ndim == 1:
            out[key] = bool(value[i])
        else:
            out[key] = value[i]
    return out


def _images(obs: Mapping[str, Any]) -> tuple[Any, Any, Any]:
    """Return the batch's ``(B, 2N)`` points, ``(B, N)`` visibility, ``(B, 2N)`` goal points."""
    if "points" in obs:
        return obs["points"], obs["visible"], obs["goal_points"]
    n = obs["observation"].shape[1] // 3  # goals with depths carry them after the 2M points
    return (
        obs["achieved_goal"][:, : 2 * n],
        obs["observation"][:, 2 * n :],
        obs["desired_goal"][:, : 2 * n],
    )


def run_batch(
    policy: Any,
    seeds: Sequence[int],
    env_id: str,
    env_kwargs: Mapping[str, Any],
    *,
    tasks: Sequence[int | None] | None = None,
    policy_name: str | None = None,
    exact: bool = True,
) -> list[EpisodeLog]:
    """Run one episode per seed, all in one native vector env; return their logs, in order.

    Parameters
    ----------
    policy
        Anything with SB3's ``predict``.
    seeds
        One reset seed per episode (``B`` episodes).
    env_id, env_kwargs
        The Gymnasium id and every ``gym.make`` keyword
        (:func:`~radial_ibvs_agents.rollouts.env_kwargs_for`).
    tasks
        The reset option ``task`` of each episode (``None``: drawn), or ``None`` for all.
    policy_name
        Name recorded in the logs.
    exact
        One ``predict`` for every robot whose episode goes on (a policy whose ``batch_mode``
        is ``"batch"``); ``False``: one ``predict`` per robot (``"robot"``).

    Returns
    -------
    list of EpisodeLog
        What :func:`~radial_ibvs_agents.rollouts.run_episode` gives for each seed alone
        (``compute_s``: the robot's share of the batch's ``predict`` time).

    Raises
    ------
    ValueError
        Where :func:`batchable` says the episodes cannot be batched, for a bad argument, or a
        learned model whose observation space differs from the env's.
    """
    why = batchable(env_id, env_kwargs)
    if why is not None:
        raise ValueError(f"these episodes cannot be batched: {why}")
    n = len(seeds)
    tasks = list(tasks) if tasks is not None else [None] * n
    venv: Any = gym.make_vec(
        env_id,
        num_envs=n,
        vectorization_mode="vector_entry_point",
        autoreset_mode="disabled",
        **env_kwargs,
    )
    try:
        if hasattr(policy, "check_observation_space"):
            policy.check_observation_space(venv.single_observation_space)
        return _run(policy, venv, [int(s) for s in seeds], tasks, policy_name, exact)
    finally:
        venv.close()


def _reset(venv: Any, seeds: list[int], tasks: list[int | None]) -> tuple[Any, list[dict]]:
    """Reset each robot with its seed and task (one reset per task, masked)."""
    n = len(seeds)
    infos: list[dict[str, Any]] = [{} for _ in range(n)]
    obs = None
    for task in dict.fromkeys(tasks):
        mask = np.array([t == task for t in tasks])
        options: dict[str, Any] = {"reset_mask": mask}
        if task is not None:
            options["task"] = task
        obs, info = venv.reset(
            seed=[s if m else None for s, m in zip(seeds, mask, strict=True)], options=options
        )
        for i in np.flatnonzero(mask).tolist():
            infos[i] = _row_of(info, i)
    return obs, infos


def _run(
    policy: Any,
    venv: Any,
    seeds: list[int],
    tasks: list[int | None],
    name: str | None,
    exact: bool,
) -> list[EpisodeLog]:
    n = len(seeds)
    obs, infos = _reset(venv, seeds, tasks)
    base = venv.unwrapped
    # the whole batch's poses, actions and images, one array per step (copies); robot i's
    # episode is its row of the first taken[i] + 1 of them (actions: taken[i])
    first_points, first_visible, _ = _images(obs)
    poses = [np.array([infos[i]["robot_pose"] for i in range(n)], dtype=np.float64)]
    points, visible = [np.array(first_points)], [np.array(first_visible)]
    actions: list[np.ndarray] = []
    taken = np.zeros(n, dtype=np.int64)
    compute = np.zeros(n)
    ended = np.zeros(n, dtype=bool)
    terminated_at = np.zeros(n, dtype=bool)
    states: list[Any] = [None] * n
    batch_state: Any = None
    starts = np.ones(n, dtype=bool)
    state_rows = np.arange(n)  # the robots batch_state describes, in its order
    while not ended.all():
        live = np.flatnonzero(~ended)
        act = np.zeros((n, 2), dtype=np.float32)
        if exact:
            # the robots whose episodes go on, alone, where the policy's state allows it
            rows = live if len(live) < len(state_rows) else state_rows
            state = _state_of(policy, batch_state, np.searchsorted(state_rows, rows))
            if state is _WHOLE_BATCH:
                rows, state = np.arange(n), batch_state
            fed = obs if len(rows) == n else {k: v[rows] for k, v in obs.items()}
            start = time.perf_counter()
            out, batch_state = policy.predict(fed, state, starts[rows], deterministic=True)
            compute[live] += (time.perf_counter() - start) / len(live)
            state_rows = rows
            act[rows] = np.asarray(out)
            act[ended] = 0.0
        else:
            for i in live.tolist():
                single = {k: v[i] for k, v in obs.items()}
                start = time.perf_counter()
                a, states[i] = policy.predict(single, states[i], starts[i : i + 1], True)
                compute[i] += time.perf_counter() - start
                act[i] = a
        starts[:] = False
        obs, _, terminated, truncated, info = venv.step(act)
        step_points, step_visible, _ = _images(obs)
        poses.append(np.array(info["robot_pose"], dtype=np.float64))
        actions.append(act.astype(np.float64))
        points.append(np.array(step_points))
        visible.append(np.array(step_visible))
        taken[live] += 1
        for i in live[(terminated | truncated)[live]].tolist():
            ended[i], terminated_at[i] = True, bool(terminated[i])
            infos[i] = _row_of(info, i)
    pose_steps, action_steps = np.stack(poses), np.stack(actions)
    point_steps, visible_steps = np.stack(points), np.stack(visible)
    goal_points = _images(obs)[2]
    logs = []
    config = base.config
    for i in range(n):
        m = visible_steps.shape[-1]
        info, t = infos[i], int(taken[i])
        logs.append(
            EpisodeLog(
                policy=name or type(policy).__name__,
                scenario=config.scenario.config.name,
                physics=config.physics,
                task=None if info.get("task") is None else int(info["task"]),
                seed=seeds[i],
                control_dt=float(config.control_dt),
                poses=pose_steps[: t + 1, i].copy(),
                actions=action_steps[:t, i].reshape(-1, 2),
                points=point_steps[: t + 1, i].astype(np.float64).reshape(-1, m, 2),
                visible=visible_steps[: t + 1, i].reshape(-1, m) > 0.5,
                goal_points=np.asarray(goal_points[i], dtype=np.float64).reshape(m, 2),
                info=info,
                compute_s=float(compute[i]),
                terminated=bool(terminated_at[i]),
                batch=n if exact else 1,
                success_hold_steps=int(config.success_hold_steps),
            )
        )
    return logs
