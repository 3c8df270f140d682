"""The parking task's rules, batched: errors, every reward term of every env id, episode end, info.

One implementation serves the scalar envs (floats, or arrays without a batch dimension) and
the native vector env (a leading ``(B,)`` batch of envs), so the two cannot drift apart:

- :func:`pose_errors`, :func:`episode_end`: how far the robot is from the goal, and when an
  episode ends;
- :func:`reward_terms`: ``Parking-v0``'s (and ``ParkingImage-v0``'s) named reward terms;
  :func:`goal_reward_terms`: ``ParkingGoal-v1``'s, all inside ``compute_reward`` (for HER);
- :func:`info_values`: the ``info`` keys every env reports, after ``reset`` and ``step``;
- :func:`real_actions`, :func:`twist_commands`: what an action may be, and the command it asks.

What the robot sees is in :mod:`~radial_ibvs_gym.envs.observation`. Pure numpy; world frame,
metres, radians. About 470 lines, one owner of the task's rules: the reward terms, the episode
end and the info read the same errors, tolerances and constants defined here.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from radial_ibvs_gym.camera import Imperfections

__all__ = [
    "ACTION_RULE",
    "GOAL_REWARD_TERMS",
    "IMPERFECTION_KEYS",
    "INFO_KEYS",
    "PARK_HOLD_S",
    "REWARD_TERMS",
    "SUCCESS_TOLERANCES",
    "TASK_TOLERANCE",
    "episode_end",
    "goal_reward_terms",
    "image_distance",
    "imperfections_info",
    "info_values",
    "park_hold_steps",
    "pose_errors",
    "potential",
    "real_actions",
    "reward_info",
    "reward_terms",
    "reward_terms_in",
    "twist_commands",
]

#: the success tolerances results are reported at (position in metres, heading in degrees):
#: the task's own (:data:`TASK_TOLERANCE`, what ``info["is_success"]`` checks by default) and
#: two looser; the one table of them (the env's defaults and every row read it)
SUCCESS_TOLERANCES: dict[str, tuple[float, float]] = {
    "2cm/2deg": (0.02, 2.0),
    "10cm/5deg": (0.10, 5.0),
    "30cm/15deg": (0.30, 15.0),
}
#: the task's own tolerance: the key of :data:`SUCCESS_TOLERANCES` the envs judge by default
TASK_TOLERANCE = "2cm/2deg"
#: how long a park holds the pose within the tolerances, seconds: the envs' default
#: ``success_hold_steps`` is this over ``control_dt`` (10 steps at 0.1 s)
PARK_HOLD_S = 1.0


def park_hold_steps(control_dt: float) -> int:
    """Return the steps of :data:`PARK_HOLD_S` at a control period (seconds), at least 1."""
    return max(1, round(PARK_HOLD_S / control_dt))


#: the reward terms, in the order they are summed (``info["reward_<term>"]``)
REWARD_TERMS = ("progress", "heading", "precision", "time", "collision", "lost", "success")


def reward_info(terms: Mapping[str, Any], convert: Any = None) -> dict[str, Any]:
    """Return the reward terms as ``info``'s flat keys, ``reward_<term>``.

    Flat scalar keys (not one nested dict) so that every ``info`` value is a number or an
    array, as Minari's ``DataCollector(record_infos=True)`` and TorchRL's info readers take
    them. The envs put them in the ``info`` of ``reset`` too (zeros), so both have one shape.

    Parameters
    ----------
    terms
        Term name -> value (a float, or a ``(B,)`` array for a batch).
    convert
        Applied to each value (e.g. ``np.float64``: one env's numbers as numpy scalars), or
        ``None``.

    Returns
    -------
    dict
        ``reward_<term>`` -> value, in the order of ``terms``.
    """
    if convert is None:
        return {f"reward_{name}": value for name, value in terms.items()}
    return {f"reward_{name}": convert(value) for name, value in terms.items()}


def reward_terms_in(info: Mapping[str, Any]) -> dict[str, Any]:
    """Return the reward terms of a step's ``info`` (the inverse of :func:`reward_info`).

    Their sum is the step's reward. ``{"progress": ..., "heading": ..., ...}`` for
    ``Parking-v0``, ``{"image_distance": ..., ...}`` for ``ParkingGoal-v1``.
    """
    return {k[len("reward_") :]: v for k, v in info.items() if k.startswith("reward_")}


#: the one rule for actions, in the scalar and the vector envs alike
ACTION_RULE = "two finite real numbers (values outside [-1, 1] are clipped to it)"


def real_actions(action: Any) -> np.ndarray:
    """Return ``action`` as float64, refusing what is not real numbers (complex, bool, text).

    NumPy would drop a complex action's imaginary part with only a warning.

    Raises
    ------
    ValueError
        For an array that is not of integers or floats, naming its dtype.
    """
    try:
        raw = np.asarray(action)
    except ValueError as error:  # ragged
        raise ValueError(f"action must be {ACTION_RULE}, got {action!r}: {error}") from None
    if raw.dtype.kind not in "iuf":
        raise ValueError(f"action must be {ACTION_RULE}, got an array of {raw.dtype}")
    return raw.astype(np.float64)


def twist_commands(actions: NDArray[np.float64], config: Any) -> NDArray[np.float64]:
    """Return the robot commands ``(N, 2)`` ``(v, omega)`` that actions ``(N, 2)`` ask for.

    The actions are clipped to ``[-1, 1]`` and scaled by ``config.scale``; with
    ``config.action_type == "wheels"`` those are the wheels' angular speeds (rad/s), turned into
    ``(v, omega)`` (m/s, rad/s) by :func:`~radial_ibvs_gym.physics.wheels_to_twist`. What the
    vector env steps and a recorded bag's ``/cmd_vel`` holds; the scalar env computes the same
    numbers on Python floats (its hot path; tested equal).

    Parameters
    ----------
    actions
        ``(N, 2)`` finite real actions (:func:`real_actions`).
    config
        The env's :class:`~radial_ibvs_gym.envs.config.ParkingConfig` (``scale``,
        ``action_type``, ``robot``).
    """
    command = np.clip(actions, -1.0, 1.0) * np.array(config.scale)
    if config.action_type == "wheels":
        from radial_ibvs_gym.physics import wheels_to_twist  # the simulator, loaded on use

        command = wheels_to_twist(command, config.robot)
    return command


_TWO_PI = 2.0 * math.pi


def _lib(x: Any) -> Any:
    """``math`` for one env's Python floats, ``numpy`` for a batch: the same operations."""
    return math if isinstance(x, float) else np


def pose_errors(pose: Sequence[Any], goal: Sequence[Any]) -> tuple[Any, Any]:
    """Position error (metres) and absolute heading error (radians) to the goal.

    Parameters
    ----------
    pose, goal
        ``(x, y, yaw)``, metres and radians: three floats (one env), or a ``(3, B)`` array
        (a batch: ``poses.T``).

    Returns
    -------
    position, heading
        Floats or ``(B,)`` arrays; the heading error is wrapped to ``[0, pi]``.
    """
    x, y, yaw = pose[0], pose[1], pose[2]
    dx, dy = x - goal[0], y - goal[1]
    position = _lib(dx).sqrt(dx * dx + dy * dy)
    # wrap to [-pi, pi) as geometry.wrap_angle does, with operators that floats and arrays share
    shifted = (yaw - goal[2] + math.pi) % _TWO_PI
    shifted = shifted - _TWO_PI * (shifted >= _TWO_PI)  # (-tiny) % 2 pi rounds up to 2 pi
    return position, abs(shifted - math.pi)


def potential(position_error: Any, heading_error: Any) -> Any:
    """Shaping potential ``phi = -ln(e_p + 0.01) - 0.5 ln(e_h + 0.02)`` (metres, radians)."""
    log = _lib(position_error).log
    return -log(position_error + 0.01) - 0.5 * log(heading_error + 0.02)


def episode_end(
    position_error: Any,
    heading_error: Any,
    n_visible: Any,
    collision: Any,
    *,
    success_position_m: float,
    success_heading_rad: float,
    min_visible: int,
    terminate_on_collision: bool,
    held: Any = 0,
    hold_steps: int = 1,
) -> tuple[Any, Any, Any, Any]:
    """Success, lost, termination and the steps held within the tolerances (``(B,)`` arrays).

    Success: both errors within the tolerances for ``hold_steps`` steps in a row (``held``:
    the steps in a row before this one; the envs' default is a park, :data:`PARK_HOLD_S`; 1:
    the first step within them, a pass counts). The returned ``held`` is 1 on the first step of
    a run within them (the envs' ``info["reached"]``). Lost:
    fewer than ``min_visible`` landmarks visible. Termination: success, lost, or a collision
    when ``terminate_on_collision``. Returns ``(success, lost, terminated, held now)``.
    """
    within = (position_error <= success_position_m) & (heading_error <= success_heading_rad)
    held = (held + 1) * within
    success = held >= hold_steps
    lost = n_visible < min_visible
    terminated = success | lost
    if terminate_on_collision:
        terminated = terminated | collision
    return success, lost, terminated, held


def reward_terms(
    previous: tuple[Any, Any],
    now: tuple[Any, Any],
    collision: Any,
    lost: Any,
    success: Any,
    weights: Mapping[str, float],
) -> dict[str, Any]:
    """Return the named reward terms of a step (their sum is the reward).

    ``progress = w_position (e_p(t-1) - e_p(t))`` (metres), ``heading = w_heading (e_h(t-1) -
    e_h(t))`` (radians), ``precision = w_precision (phi(t) - phi(t-1))`` (:func:`potential`:
    potential-based shaping, which keeps the optimal policy), ``time = -time_penalty``,
    ``collision = -collision_penalty``, ``lost = -lost_penalty``, ``success =
    success_bonus``, each on its event.

    Parameters
    ----------
    previous, now
        ``(position error, heading error)`` before and after the step: floats, or ``(B,)``.
    collision, lost, success
        The step's events: bools, or ``(B,)`` bool arrays.
    weights
        ``w_position``, ``w_heading``, ``w_precision``, ``time_penalty``,
        ``collision_penalty``, ``lost_penalty``, ``success_bonus``.

    Returns
    -------
    dict
        :data:`REWARD_TERMS` -> floats or ``(B,)`` arrays, in summation order.
    """
    (p0, h0), (p1, h1) = previous, now
    zero = 0.0 * p1
    w = weights["w_precision"]
    return {
        "progress": weights["w_position"] * (p0 - p1),
        "heading": weights["w_heading"] * (h0 - h1),
        "precision": w * (potential(p1, h1) - potential(p0, h0)) if w else zero,
        "time": zero - weights["time_penalty"],
        "collision": -weights["collision_penalty"] * (collision + zero),
        "lost": -weights["lost_penalty"] * (lost + zero),
        "success": weights["success_bonus"] * (success + zero),
    }


#: the keys of ``info["camera_imperfections"]``, in this order
IMPERFECTION_KEYS = (
    "principal_point_du",
    "principal_point_dv",
    "focal_ratio_error",
    "pixel_noise_std",
    "tilt_x",
    "tilt_y",
)


def imperfections_info(imperfections: Imperfections) -> dict[str, float]:
    """Return drawn camera imperfections as plain values (``info["camera_imperfections"]``).

    Keys: ``principal_point_du``, ``principal_point_dv`` (pixels), ``focal_ratio_error``,
    ``pixel_noise_std`` (pixels), ``tilt_x``, ``tilt_y`` (radians).
    """
    du, dv = imperfections.principal_point_offset
    tx, ty = imperfections.tilt
    return {
        "principal_point_du": float(du),
        "principal_point_dv": float(dv),
        "focal_ratio_error": float(imperfections.focal_ratio_error),
        "pixel_noise_std": float(imperfections.pixel_noise_std),
        "tilt_x": float(tx),
        "tilt_y": float(ty),
    }


#: ``ParkingGoal-v1``'s reward terms, in the order they are summed
GOAL_REWARD_TERMS = ("image_distance", "collision", "lost", "success")


def image_distance(achieved_goal: Any, desired_goal: Any) -> NDArray[np.float64]:
    """``D``: the mean absolute coordinate difference over the landmarks in either image.

    Parameters
    ----------
    achieved_goal, desired_goal
        ``(..., 2M)`` flattened normalised image points (zeros where hidden).

    Returns
    -------
    numpy.ndarray
        ``(...)``, >= 0 (0 where no landmark is seen in either image).
    """
    a = np.asarray(achieved_goal, dtype=np.float64)
    d = np.asarray(desired_goal, dtype=np.float64)
    a, d = a.reshape(*a.shape[:-1], -1, 2), d.reshape(*d.shape[:-1], -1, 2)
    used = (np.hypot(a[..., 0], a[..., 1]) > 0.5) | (np.hypot(d[..., 0], d[..., 1]) > 0.5)
    total = np.sum(np.abs(a - d).sum(axis=-1) * used, axis=-1)
    return np.asarray(total / np.maximum(2.0 * used.sum(axis=-1), 1.0))


def _flags(info: Any, key: str, shape: tuple[int, ...]) -> NDArray[np.float64]:
    """``info[key]`` as a float array of ``shape``, for one info or a batch of them.

    ``info`` is one step's dict (a bool), a vector env's dict (an array), or a sequence of
    dicts, as stable-baselines3's ``HerReplayBuffer`` passes them (one per relabelled step).
    """
    if isinstance(info, dict):
        value = np.asarray(info.get(key, False), dtype=np.float64)
    elif info is None:
        value = np.zeros(shape)
    else:
        value = np.array([bool(i.get(key, False)) for i in np.ravel(info)], dtype=np.float64)
    try:
        return np.broadcast_to(value.reshape(value.shape or ()), shape)
    except ValueError:
        raise ValueError(
            f"info[{key!r}] has {value.size} value(s) for {int(np.prod(shape))} goal(s)"
        ) from None


def goal_reward_terms(
    achieved_goal: Any,
    desired_goal: Any,
    info: Any,
    weights: Mapping[str, float],
    power: float,
    tolerance: float,
) -> dict[str, NDArray[np.float64]]:
    """Return ``ParkingGoal-v1``'s named reward terms; their sum is ``compute_reward``.

    ``image_distance = -D ** power`` (:func:`image_distance`), ``collision =
    -collision_penalty`` and ``lost = -lost_penalty`` (read from ``info["collision"]`` and
    ``info["lost"]``, so HER's relabelled transitions keep them), ``success = success_bonus``
    where ``D <= tolerance`` (success in the image, which a relabelled goal has too).

    Parameters
    ----------
    achieved_goal, desired_goal
        ``(..., 2M)`` flattened normalised image points (batched for HER).
    info
        One step's ``info``, a vector env's batched ``info``, or a sequence of per-step
        ``info`` dicts (HER); ``None`` counts no collision and no loss.
    weights
        ``collision_penalty``, ``lost_penalty``, ``success_bonus``.
    power, tolerance
        The env's ``goal_reward_power`` and ``goal_image_tolerance``.
    """
    distance = image_distance(achieved_goal, desired_goal)
    return {
        "image_distance": -np.power(distance, power),
        "collision": -weights["collision_penalty"] * _flags(info, "collision", distance.shape),
        "lost": -weights["lost_penalty"] * _flags(info, "lost", distance.shape),
        "success": weights["success_bonus"] * (distance <= tolerance),
    }


#: the keys of ``info`` after ``reset`` and ``step``, beside the reward terms' ``reward_<term>``
INFO_KEYS = (
    "robot_pose",
    "goal_pose",
    "position_error_m",
    "heading_error_deg",
    "is_success",
    "reached",
    "collision",
    "lost",
    "n_visible",
    "task",
    "goal_depths",
)


def info_values(
    pose: Any,
    goal: Any,
    errors: tuple[Any, Any],
    success: Any,
    collision: Any,
    lost: Any,
    n_visible: Any,
    task: Any,
    goal_depths: Any,
    imperfections: Mapping[str, Any] | None = None,
    *,
    reached: Any = False,
) -> dict[str, Any]:
    """Build the ``info`` values of one env (plain Python scalars) or of a batch (arrays).

    Parameters
    ----------
    pose, goal
        ``(..., 3)`` the robot's and the goal's ``(x, y, yaw)``, metres and radians (copied).
    errors
        ``(position error, heading error)``: metres and radians (:func:`pose_errors`); floats
        for one env, ``(B,)`` arrays for a batch.
    success, collision, lost, n_visible, task
        The step's events, the visible landmarks and the task index: scalars or ``(B,)``.
    goal_depths
        ``(..., N)`` the goal depths ``d*``, metres (copied).
    imperfections
        The drawn camera imperfections (:func:`imperfections_info`; ``(B,)`` arrays for a
        batch), or ``None`` when the scenario draws none.
    reached
        Whether this step is the first of a run within the tolerances (``held == 1``): the
        step a pass would count. ``is_success`` comes ``success_hold_steps - 1`` steps later,
        if the pose stays.

    Returns
    -------
    dict
        :data:`INFO_KEYS`, plus ``camera_imperfections`` when drawn; ``heading_error_deg``
        in degrees. One env's numbers are numpy scalars (``np.float64``, ``np.int64``) or
        arrays, each with a ``dtype`` as TorchRL's info reader needs; its flags
        (``is_success``, ``reached``, ``collision``, ``lost``) are Python bools, which
        Gymnasium's vector envs batch as bool arrays.
    """
    values: dict[str, Any]
    if isinstance(errors[0], np.ndarray) and errors[0].ndim > 0:  # a batch
        values = {
            "robot_pose": np.array(pose, dtype=np.float64),
            "goal_pose": np.array(goal, dtype=np.float64),
            "position_error_m": np.asarray(errors[0]).astype(np.float64),
            "heading_error_deg": np.degrees(errors[1]),
            "is_success": np.asarray(success, dtype=bool),
            "reached": np.broadcast_to(np.asarray(reached, dtype=bool), errors[0].shape).copy(),
            "collision": np.asarray(collision, dtype=bool),
            "lost": np.asarray(lost, dtype=bool),
            "n_visible": np.asarray(n_visible, dtype=np.int64),
            "task": np.array(task, dtype=np.int64),
        }
    else:
        # numbers as numpy scalars (TorchRL's info reader reads each value's dtype), flags as
        # Python bools (Gymnasium's SyncVectorEnv batches np.bool_ as an object array)
        values = {
            "robot_pose": np.array(pose, dtype=np.float64),
            "goal_pose": np.array(goal, dtype=np.float64),
            "position_error_m": np.float64(errors[0]),
            "heading_error_deg": np.float64(math.degrees(errors[1])),
            "is_success": bool(success),
            "reached": bool(reached),
            "collision": bool(collision),
            "lost": bool(lost),
            "n_visible": np.int64(n_visible),
            "task": np.int64(task),
        }
    values["goal_depths"] = np.array(goal_depths)
    if imperfections is not None:
        values["camera_imperfections"] = dict(imperfections)
    return values
