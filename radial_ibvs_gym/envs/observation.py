"""What the robot sees, batched: image points, visibility, features, the observation dict.

One implementation serves the scalar envs (:class:`~radial_ibvs_gym.envs.parking.ParkingEnv`,
no batch dimension) and the native vector env
(:class:`~radial_ibvs_gym.envs.parking_vector.ParkingVectorEnv`, a leading ``(B,)`` batch of
envs): every function is elementwise over leading dimensions, so the two cannot drift apart.
The task's rules (errors, reward, episode end, ``info``) are in :mod:`~radial_ibvs_gym.envs.rules`.
Frames and units as everywhere (world frame, metres, radians). Measuring through an imperfect
camera is in :mod:`~radial_ibvs_gym.camera.measurement`, the landmark slots in
:mod:`~radial_ibvs_gym.envs.slots`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from radial_ibvs_gym.envs.slots import Slots

if TYPE_CHECKING:
    from gymnasium import spaces

    from radial_ibvs_gym.envs.config import ParkingConfig

__all__ = [
    "goal_observation",
    "observation",
    "observation_space",
    "radial_image",
]

Array = NDArray[np.float64]


def radial_image(
    landmarks: NDArray[np.complex128], radius_lo: Array, radius_hi: Array, pose: Array
) -> tuple[Array, NDArray[np.bool_]]:
    """Normalised image points of an ideal on-axis camera (eq. 9), with visibility.

    An ideal camera gives eq. (9) exactly, so the points are the landmarks' horizontal
    bearings in the camera frame; a landmark is visible when its horizontal distance lies in
    the interval the mirror sees at its height
    (:meth:`~radial_ibvs_gym.camera.CatadioptricCamera.visible_radius_bounds`).

    Parameters
    ----------
    landmarks
        ``(..., N)`` landmark positions on the floor plane as complex numbers ``x + i y``,
        world frame, metres (one complex multiplication rotates them into the camera frame).
    radius_lo, radius_hi
        ``(..., N)`` the visible interval of horizontal distances of each landmark, metres.
    pose
        ``(..., 3)`` robot (= camera) pose ``(x, y, yaw)``, metres and radians.

    Returns
    -------
    points
        ``(..., N, 2)`` unit vectors ``x_n`` in the camera frame, zeros where hidden.
    visible
        ``(..., N)`` visibility.
    """
    pose = np.asarray(pose, dtype=np.float64)
    if pose.ndim == 1:  # one robot: the pose as Python numbers (the same bits, fewer calls)
        x, y, yaw = pose.tolist()
        w = (landmarks - complex(x, y)) * complex(math.cos(yaw), -math.sin(yaw))
    else:
        position = pose[..., :2].view(np.complex128)  # (..., 1): x + i y, no copy
        turn = np.exp(-1j * pose[..., 2:3])  # the world -> camera rotation about the axis
        w = (landmarks - position) * turn
    rho = np.abs(w)
    visible = (rho > radius_lo) & (rho < radius_hi)
    w *= visible / np.maximum(rho, 1e-300)
    return w.view(np.float64).reshape(*w.shape, 2), visible


def observation(
    points: Array,
    goal_points: Array,
    visible: NDArray[np.bool_],
    *,
    features: Mapping[str, Array] | None = None,
    goal_depths: Array | None = None,
    robot_pose: Array | None = None,
    goal_pose: Array | None = None,
    landmarks: NDArray[np.complex128] | None = None,
    slots: Slots | None = None,
    slot_order: NDArray[np.intp] | None = None,
    present: NDArray[np.bool_] | None = None,
) -> dict[str, NDArray[Any]]:
    """Build the ``Parking-v0`` observation dict, in the spaces' dtypes (``(...)`` leading dims).

    Parameters
    ----------
    points, goal_points
        ``(..., 2N)`` current and goal image points, flattened (zeros where hidden).
    visible
        ``(..., N)`` visibility now.
    features
        ``c_error`` ``(..., M)`` and ``alpha_m_error`` ``(..., 1)`` (``obs_mode="features"``);
        ``c_error`` is clipped to ``[-2, 2]``.
    goal_depths
        ``(..., N)`` goal depths ``d*``, metres (``goal_depths=True``).
    robot_pose, goal_pose, landmarks
        The privileged observation (``privileged=True``): poses ``(..., 3)`` and the landmarks
        ``(..., N)`` (complex ``x + i y``) whose horizontal distances to the robot become
        ``depths``.
    slots
        Pad the landmark axis to a fixed number of slots
        (:class:`~radial_ibvs_gym.envs.slots.Slots`, the env's ``max_landmarks``), with
        zeros, and add ``landmark_mask`` (1 for the scene's landmarks): one observation
        space for any scene with at most that many landmarks.
    slot_order
        With ``slots``: ``(..., N)`` the slot of each landmark (``None``: landmark ``n`` in
        slot ``n``; :meth:`~radial_ibvs_gym.envs.slots.Slots.pad`).
    present
        ``(..., N)`` which landmarks the episode has (a drawn landmark count; ``None``: all).
        The absent ones have privileged ``depths`` of 0 and, with ``slots``, a
        ``landmark_mask`` of 0.
    """
    obs: dict[str, NDArray[Any]] = {
        "points": np.asarray(points, dtype=np.float32),
        "goal_points": np.asarray(goal_points, dtype=np.float32),
        "visible": np.asarray(visible, dtype=np.float32),
    }
    if features:
        obs["c_error"] = np.clip(features["c_error"], -2.0, 2.0).astype(np.float32)
        obs["alpha_m_error"] = np.asarray(features["alpha_m_error"], dtype=np.float32)
    if goal_depths is not None:
        obs["goal_depths"] = np.asarray(goal_depths, dtype=np.float32)
    if robot_pose is not None and goal_pose is not None and landmarks is not None:
        pose = np.asarray(robot_pose, dtype=np.float64)
        obs["robot_pose"] = pose.copy()
        obs["goal_pose"] = np.asarray(goal_pose, dtype=np.float64).copy()
        position = pose[..., 0:1] + 1j * pose[..., 1:2]
        depths = np.abs(landmarks - position)
        if present is not None:
            depths = np.where(present, depths, 0.0)
        obs["depths"] = depths.astype(np.float32)
    return obs if slots is None else slots.pad(obs, slot_order, present)


def goal_observation(
    points: Array,
    visible: NDArray[np.bool_],
    goal_points: Array,
    depths: Array | None = None,
    goal_depths: Array | None = None,
) -> dict[str, NDArray[np.float32]]:
    """Build the ``ParkingGoal-v1`` observation dict (goal-conditioned, for HER).

    ``points``, ``goal_points``: ``(..., 2N)`` flattened image points; ``visible``: ``(..., N)``.
    With ``depths`` and ``goal_depths`` (``(..., N)``, metres: the depths that come with the
    current image, were it a goal image, and the goal depths ``d*``), each goal is the image
    points followed by its depths, ``(..., 3N)``.
    """
    achieved = np.asarray(points, dtype=np.float32)
    desired = np.asarray(goal_points, dtype=np.float32)
    observation = np.concatenate([achieved, np.asarray(visible, dtype=np.float32)], axis=-1)
    if depths is not None and goal_depths is not None:
        achieved = np.concatenate([achieved, np.asarray(depths, dtype=np.float32)], axis=-1)
        desired = np.concatenate([desired, np.asarray(goal_depths, dtype=np.float32)], axis=-1)
    return {"observation": observation, "achieved_goal": achieved, "desired_goal": desired}


def observation_space(config: ParkingConfig) -> spaces.Dict:
    """Return ``Parking-v0``'s observation space for ``config`` (see ``ParkingEnv``'s table).

    ``K`` landmark entries (the slots, or the scene's landmarks; ``M = K (K - 1) / 2``):
    ``points``, ``goal_points`` ``(2K,)``, ``visible`` ``(K,)``; ``c_error`` ``(M,)`` and
    ``alpha_m_error`` ``(1,)`` with ``obs_mode="features"``; ``goal_depths`` ``(K,)``
    (metres); with ``privileged``, ``robot_pose``, ``goal_pose`` ``(3,)`` and ``depths``
    ``(K,)``; with ``privileged_map``, ``room``, ``obstacles``, ``landmarks`` and
    ``landmark_range``; with slots, ``landmark_mask`` ``(K,)``.
    """
    from gymnasium import spaces

    k = config.observed_landmarks
    obs_spaces: dict[str, spaces.Space[Any]] = {
        "points": spaces.Box(-1.0, 1.0, (2 * k,), np.float32),
        "goal_points": spaces.Box(-1.0, 1.0, (2 * k,), np.float32),
        "visible": spaces.Box(0.0, 1.0, (k,), np.float32),
    }
    if config.obs_mode == "features":
        m = k * (k - 1) // 2
        obs_spaces["c_error"] = spaces.Box(-2.0, 2.0, (m,), np.float32)
        obs_spaces["alpha_m_error"] = spaces.Box(-np.pi, np.pi, (1,), np.float32)
    depth_space = spaces.Box(0.0, 1e3, (k,), np.float32)  # metres
    if config.goal_depths:
        obs_spaces["goal_depths"] = depth_space
    if config.privileged:
        bound = np.array([1e3, 1e3, np.pi])  # metres, metres, radians (yaw wrapped)
        pose_space = spaces.Box(-bound, bound, (3,), np.float64)
        obs_spaces["robot_pose"] = pose_space
        obs_spaces["goal_pose"] = pose_space
        obs_spaces["depths"] = depth_space
    if config.privileged_map:
        obs_spaces["room"] = spaces.Box(0.0, 1e3, (2,), np.float64)
        obs_spaces["obstacles"] = spaces.Box(-1e3, 1e3, (config.map_obstacles, 3), np.float64)
        obs_spaces["landmarks"] = spaces.Box(-1e3, 1e3, (k, 3), np.float64)
        obs_spaces["landmark_range"] = spaces.Box(0.0, 1e3, (k, 2), np.float64)
    if config.slots is not None:
        obs_spaces["landmark_mask"] = spaces.Box(0.0, 1.0, (k,), np.float32)
    return spaces.Dict(obs_spaces)
