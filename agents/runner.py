"""The one episode runner: make the env a policy needs, run it, keep what tables need.

Every command and notebook goes through here (``evaluate``, ``benchmark``, ``reproduce``,
``render``, ``demo``, the notebooks' helpers), so they all build the env the same way:

- :func:`env_kwargs_for` merges the ``gym.make`` keywords in one order: the policy's
  ``env_kwargs`` (what its observation needs, and for a learned model the settings it was
  trained with), then the scenario, then the caller's overrides, which win;
- :func:`make_env` makes the env and checks that a learned model's observation space fits;
- :func:`run_episode` steps a policy (anything with SB3's ``predict``) in the env and returns
  an :class:`EpisodeLog` with the trajectory, the observations, optionally the rendered
  frames, and the metrics of the ``--json`` rows (:meth:`EpisodeLog.row`).
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import gymnasium as gym
import numpy as np
from numpy.typing import NDArray

from radial_ibvs_gym.envs.rules import SUCCESS_TOLERANCES
from radial_ibvs_gym.registration import check_env_id

__all__ = [
    "DEFAULT_ENV_ID",
    "RUN_FIELDS",
    "TOLERANCES",
    "EpisodeLog",
    "env_kwargs_for",
    "make_env",
    "run_episode",
]

#: a row's fields that describe how it was run, not the episode: the policy's compute per step
#: (a timing) and how many robots one ``predict`` served (set by the benchmark's chunking)
RUN_FIELDS = ("compute_us_per_step", "compute_batch")

#: the success tolerances every row reports (position in metres, heading in degrees): the
#: env's own (2 cm / 2 deg, the ``success`` column) and two looser ones
TOLERANCES = SUCCESS_TOLERANCES

#: the env every command runs unless told otherwise
DEFAULT_ENV_ID = "RadialIBVS/Parking-v0"


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
    given = env_id or getattr(policy, "env_id", None) or DEFAULT_ENV_ID
    env_id = check_env_id(given, "env_id" if env_id else f"{policy!r}: env_id")
    env = gym.make(env_id, **make_kwargs, **env_kwargs_for(policy, scenario, overrides))
    if hasattr(policy, "check_observation_space"):
        try:
            policy.check_observation_space(env.observation_space)
        except ValueError:
            env.close()
            raise
    return env


def _image(obs: Mapping[str, Any]) -> tuple[Any, Any, Any]:
    """Return the current points, their visibility and the goal points of an observation.

    ``Parking-v0`` has them as ``points``, ``visible`` and ``goal_points``; the goal-conditioned
    ``ParkingGoal-v1`` as ``achieved_goal``, the last third of ``observation`` and
    ``desired_goal`` (their first ``2M`` values: with ``goal_depths=True`` the depths follow).
    """
    if "points" in obs:
        return obs["points"], obs["visible"], obs["goal_points"]
    n = len(obs["observation"]) // 3
    return (
        obs["achieved_goal"][: 2 * n],
        obs["observation"][2 * n :],
        obs["desired_goal"][: 2 * n],
    )


@dataclass
class EpisodeLog:
    """One episode of a policy in a ``Parking-v0``-like env.

    Attributes
    ----------
    policy, scenario, physics
        Names (the policy's as given to :func:`run_episode`).
    task, seed
        The episode's task index and reset seed.
    control_dt
        Control period, seconds.
    poses
        ``(T + 1, 3)`` robot poses ``(x, y, yaw)`` from the reset on, metres and radians.
    actions
        ``(T, 2)`` actions in ``[-1, 1]``.
    points, visible
        ``(T + 1, N, 2)`` observed image points ``x_n`` (zeros where hidden) and ``(T + 1, N)``
        visibility.
    goal_points
        ``(N, 2)`` the goal image ``x_n*``.
    info
        The last ``info``.
    compute_s
        Seconds spent in ``predict`` over the episode (stepped in a batch: the robot's share).
    batch
        Robots whose actions one ``predict`` gave together at the episode's start (1: alone).
    frames
        ``(T + 1)`` rendered ``(H, W, 3)`` uint8 frames, when :func:`run_episode` was asked to
        record them; empty otherwise.
    extra
        Anything a caller adds (e.g. the suite).
    terminated
        Whether the env terminated the episode (success, collision or lost landmarks) rather
        than truncated it (time limit) or ``max_steps`` stopped it.
    success_hold_steps
        How the env judged success: steps in a row within the tolerances (1: the first step
        within them).
    """

    policy: str
    scenario: str
    physics: str
    task: int | None
    seed: int
    control_dt: float
    poses: NDArray[np.float64]
    actions: NDArray[np.float64]
    points: NDArray[np.float64]
    visible: NDArray[np.bool_]
    goal_points: NDArray[np.float64]
    info: dict[str, Any]
    compute_s: float
    extra: dict[str, Any] = field(default_factory=dict)
    batch: int = 1
    terminated: bool = False
    success_hold_steps: int = 1
    frames: list[NDArray[np.uint8]] = field(default_factory=list, repr=False)

    @property
    def steps(self) -> int:
        """Number of steps taken."""
        return len(self.actions)

    @property
    def times(self) -> NDArray[np.float64]:
        """``(T + 1,)`` time of each pose, seconds."""
        return np.asarray(self.control_dt * np.arange(self.steps + 1), dtype=np.float64)

    @property
    def path_length_m(self) -> float:
        """Length of the driven path, metres."""
        return float(np.linalg.norm(np.diff(self.poses[:, :2], axis=0), axis=1).sum())

    @property
    def control_effort(self) -> float:
        """Mean squared action (actions are fractions of the speed limits), 0 to 2."""
        if self.steps == 0:
            return 0.0
        return float(np.mean(np.sum(self.actions**2, axis=1)))

    @property
    def smoothness(self) -> float:
        """Mean change of the action from one step to the next (0: perfectly smooth)."""
        if self.steps < 2:
            return 0.0
        return float(np.mean(np.linalg.norm(np.diff(self.actions, axis=0), axis=1)))

    @property
    def success(self) -> bool:
        """Whether the env reported success at the end."""
        return bool(self.info.get("is_success", False))

    @property
    def end(self) -> str:
        """Why the episode ended: ``success``, ``collision``, ``lost`` or ``time-out``."""
        if self.success:
            return "success"
        if self.info.get("collision", False):
            return "collision"
        return "lost" if self.terminated else "time-out"

    def success_at(self, position_m: float, heading_deg: float) -> bool:
        """Success at a looser tolerance: the env's success, or a final pose that close.

        An episode ended by a collision counts only if the env reported success.
        """
        if self.success:
            return True
        return (
            not self.info.get("collision", False)
            and float(self.info["position_error_m"]) <= position_m
            and float(self.info["heading_error_deg"]) <= heading_deg
        )

    def row(self) -> dict[str, Any]:
        """Return the episode as a ``--json`` row (README, "JSON rows"), plus ``extra``."""
        steps = max(self.steps, 1)
        return {
            "policy": self.policy,
            "scenario": self.scenario,
            "suite": self.extra.get("suite"),
            "task": self.task,
            "seed": self.seed,
            "physics": self.physics,
            "success": self.success,
            "final_position_error_m": float(self.info["position_error_m"]),
            "final_heading_error_deg": float(self.info["heading_error_deg"]),
            "steps": self.steps,
            "time_s": round(self.steps * self.control_dt, 9),
            "path_length_m": self.path_length_m,
            "collision": bool(self.info.get("collision", False)),
            "end": self.end,
            "success_hold_steps": self.success_hold_steps,
            "success_by_tolerance": {
                name: self.success_at(*tol) for name, tol in TOLERANCES.items()
            },
            "compute_us_per_step": 1e6 * self.compute_s / steps,
            "compute_batch": self.batch,
            "control_effort": self.control_effort,
            "smoothness": self.smoothness,
            **(
                {"camera_imperfections": self.info["camera_imperfections"]}
                if "camera_imperfections" in self.info
                else {}
            ),
            **{k: v for k, v in self.extra.items() if k != "suite"},
        }


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
        points=np.array(points, dtype=np.float64).reshape(-1, n, 2),
        visible=np.array(visible).reshape(-1, n) > 0.5,
        goal_points=np.asarray(image[2], dtype=np.float64).reshape(n, 2),
        info=info,
        compute_s=compute,
        frames=frames,
        terminated=terminated,
        success_hold_steps=int(getattr(getattr(base, "config", None), "success_hold_steps", 1)),
    )
