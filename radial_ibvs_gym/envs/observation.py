"""What the robot sees, batched: image points, visibility, features, the observation dict.

One implementation serves the scalar envs (:class:`~radial_ibvs_gym.envs.parking.ParkingEnv`,
no batch dimension) and the native vector env
(:class:`~radial_ibvs_gym.envs.parking_vector.ParkingVectorEnv`, a leading ``(B,)`` batch of
envs): every function is elementwise over leading dimensions, so the two cannot drift apart.
The task's rules (errors, reward, episode end, ``info``) are in :mod:`~radial_ibvs_gym.envs.rules`.
Frames and units as everywhere (world frame, metres, radians). A little over 450 lines, kept
whole: one job (the observation), shared by both envs, and splitting it would split that contract.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from radial_ibvs_gym.camera import CatadioptricCamera, normalise_pixels
from radial_ibvs_gym.camera.batch import forward_batch, shares_reflection
from radial_ibvs_gym.features import c_ij, virtual_point_weights
from radial_ibvs_gym.geometry import wrap_angle
from radial_ibvs_gym.limits import MAX_LANDMARKS

if TYPE_CHECKING:
    from gymnasium import spaces

    from radial_ibvs_gym.envs.config import ParkingConfig

__all__ = [
    "Slots",
    "camera_image",
    "camera_images",
    "feature_errors",
    "goal_observation",
    "goal_weights",
    "observation",
    "observation_space",
    "radial_image",
    "unit_or_dummy",
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


def camera_image(
    camera: CatadioptricCamera, p_cam: Array, rng: np.random.Generator | None
) -> tuple[Array, NDArray[np.bool_]]:
    """Normalised image points of a real camera, measured as the paper's set-up does.

    Exact projection through the mirror with the true intrinsics, tilt and offset, pixel noise
    from ``rng``, then eq. (7) with the *nominal* principal point and ``rho_f``. An ideal
    concave (self-occluding) mirror is handled exactly without the projection.

    Parameters
    ----------
    camera
        The camera (one env's).
    p_cam
        ``(N, 3)`` landmarks in the camera frame, metres.
    rng
        The env's generator (pixel noise); ``None``: no noise.

    Returns
    -------
    points, visible
        ``(N, 2)`` (zeros where hidden) and ``(N,)``.
    """
    if not camera.imperfections.any:  # an on-axis concave mirror: exact visibility
        visible = camera.visible(p_cam, validate=False)
        d = np.hypot(p_cam[:, 0], p_cam[:, 1])
        return p_cam[:, :2] * (visible / np.maximum(d, 1e-300))[:, None], visible
    proj = camera.forward(p_cam, rng=rng)
    k = camera.intrinsics
    pixels = np.where(proj.visible[:, None], proj.pixels, k.principal_point + 1.0)
    x_n = normalise_pixels(pixels, k.principal_point, k.rho_f)
    return np.where(proj.visible[:, None], x_n, 0.0), proj.visible


def camera_images(
    cameras: Sequence[CatadioptricCamera],
    p_cam: Array,
    rngs: Sequence[np.random.Generator | None],
) -> tuple[Array, NDArray[np.bool_]]:
    """:func:`camera_image` for ``K`` cameras at once, each with its own generator.

    The cameras with imperfections that share the mirror's reflection
    (:func:`~radial_ibvs_gym.camera.batch.shares_reflection`) are projected in one batched
    root-find (:func:`~radial_ibvs_gym.camera.batch.forward_batch`); the result is, row for
    row and bit for bit, what :func:`camera_image` gives each camera.

    Parameters
    ----------
    cameras
        ``K`` cameras (one per env).
    p_cam
        ``(K, N, 3)`` landmarks, row ``k`` in camera ``k``'s frame, metres.
    rngs
        ``K`` generators (pixel noise; ``None``: none).

    Returns
    -------
    points, visible
        ``(K, N, 2)`` (zeros where hidden) and ``(K, N)``.
    """
    k, n = p_cam.shape[:2]
    points = np.zeros((k, n, 2))
    visible = np.zeros((k, n), dtype=bool)
    batched = [i for i, c in enumerate(cameras) if c.imperfections.any]
    for i in sorted(set(range(k)) - set(batched)):
        points[i], visible[i] = camera_image(cameras[i], p_cam[i], rngs[i])
    group = [cameras[i] for i in batched]
    if len(group) < 2 or not shares_reflection(group):
        for i in batched:
            points[i], visible[i] = camera_image(cameras[i], p_cam[i], rngs[i])
        return points, visible
    proj = forward_batch(group, p_cam[batched], [rngs[i] for i in batched])
    nominal = group[0].intrinsics  # shared by the group
    pixels = np.where(proj.visible[..., None], proj.pixels, nominal.principal_point + 1.0)
    x_n = normalise_pixels(pixels, nominal.principal_point, nominal.rho_f)
    points[batched] = np.where(proj.visible[..., None], x_n, 0.0)
    visible[batched] = proj.visible
    return points, visible


def unit_or_dummy(points: Array, mask: NDArray[np.bool_]) -> Array:
    """Hidden points (zeros) replaced by ``(1, 0)``: the features need unit vectors.

    The pairs with a hidden point are masked out afterwards.
    """
    return np.where(mask[..., None], points, np.array([1.0, 0.0]))


def goal_weights(goal_points: Array, mask: NDArray[np.bool_]) -> Array | None:
    """Virtual-point weights (eq. 27-29) of the goal points in ``mask``, as an ``(N,)`` vector.

    Zero outside ``mask``; ``None`` when fewer than 2 points are in it or they are collinear
    with the axis (no virtual point).
    """
    if mask.sum() < 2:
        return None
    try:
        a = virtual_point_weights(goal_points[mask])
    except ValueError:  # goal points collinear with the axis: no virtual point
        return None
    full = np.zeros(mask.shape, dtype=np.float64)
    full[mask] = a
    return full


def feature_errors(
    points: Array,
    both: NDArray[np.bool_],
    c_goal: Array,
    pairs: tuple[NDArray[np.intp], NDArray[np.intp]],
    weights: Array,
    has_weights: Any,
) -> tuple[Array, Array]:
    """Feature errors ``c*_ij - c_ij`` and ``alpha_m* - alpha_m`` (eq. 12, 19-29).

    Parameters
    ----------
    points
        ``(..., N, 2)`` current image points (zeros where hidden).
    both
        ``(..., N)`` visible now and in the goal image.
    c_goal
        ``(..., M)`` the goal image's ``c*_ij``.
    pairs
        The ``(i, j)`` index arrays of the ``M`` pairs.
    weights
        ``(..., N)`` the goal's virtual-point weights over ``both`` (:func:`goal_weights`; zero
        outside ``both``).
    has_weights
        ``(...)`` whether a virtual point exists (else ``alpha_m`` error is 0).

    Returns
    -------
    c_error
        ``(..., M)``, 0 for pairs with a point not in ``both``.
    alpha_m_error
        ``(..., 1)`` radians: the goal's virtual point is ``(1, 0)`` by construction, so the
        error is ``-alpha_m`` of the current virtual point ``sum_i a_i x_ni``.
    """
    i, j = pairs
    pair_ok = both[..., i] & both[..., j]
    c_now = c_ij(unit_or_dummy(points, both))
    c_err = np.where(pair_ok, c_goal - c_now, 0.0)
    p_now = (weights[..., None] * points).sum(axis=-2)
    alpha = np.where(has_weights, wrap_angle(-np.arctan2(p_now[..., 1], p_now[..., 0])), 0.0)
    return c_err, alpha[..., None]


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
        Pad the landmark axis to a fixed number of slots (:class:`Slots`, the env's
        ``max_landmarks``), with zeros, and add ``landmark_mask`` (1 for the scene's
        landmarks): one observation space for any scene with at most that many landmarks.
    slot_order
        With ``slots``: ``(..., N)`` the slot of each landmark (``None``: landmark ``n`` in
        slot ``n``; :meth:`Slots.pad`).
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
        obs["depths"] = np.abs(landmarks - position).astype(np.float32)
    return obs if slots is None else slots.pad(obs, slot_order)


class Slots:
    """A fixed number of landmark slots: pads observations of ``N <= M`` landmarks to ``M``.

    Parameters
    ----------
    n
        The scene's landmarks ``N``.
    m
        The slots ``M`` (>= ``N``).
    """

    #: the keys with one entry per landmark, and how many values per entry
    PER_LANDMARK: Mapping[str, int] = {
        "points": 2,
        "goal_points": 2,
        "visible": 1,
        "goal_depths": 1,
        "depths": 1,
    }

    def __init__(self, n: int, m: int) -> None:
        if not (2 <= n <= m):
            raise ValueError(f"max_landmarks must be >= the scene's {n} landmarks, got {m!r}")
        if m > MAX_LANDMARKS:
            raise ValueError(
                f"max_landmarks must be at most MAX_LANDMARKS = {MAX_LANDMARKS}, got {m}"
            )
        self.n, self.m = int(n), int(m)
        i, j = np.triu_indices(n, 1)
        # the position of pair (i, j) among the M slots' pairs, in row-major order
        self.pair_slots = (i * (2 * m - i - 1)) // 2 + (j - i - 1)
        self.mask = np.zeros(m, dtype=np.float32)
        self.mask[:n] = 1.0

    def pair_index(self, order: NDArray[np.intp]) -> NDArray[np.intp]:
        """Return where each landmark pair ``(i, j)``, ``i < j``, lies among the slots' pairs.

        Parameters
        ----------
        order
            ``(..., N)`` the slot of each landmark (distinct, in ``0..M-1``).

        Returns
        -------
        ``(..., N (N - 1) / 2)`` indices into the ``M (M - 1) / 2`` pairs, in row-major order
        of the slots (a pair is unordered: ``c_ij`` is symmetric).
        """
        i, j = np.triu_indices(self.n, 1)
        a = np.minimum(order[..., i], order[..., j])
        b = np.maximum(order[..., i], order[..., j])
        return (a * (2 * self.m - a - 1)) // 2 + (b - a - 1)

    def draw_order(self, rng: np.random.Generator) -> NDArray[np.intp]:
        """Draw the slots of an episode's landmarks: ``(N,)`` distinct slots in ``0..M-1``."""
        return rng.permutation(self.m)[: self.n].astype(np.intp)

    def pad(
        self, obs: dict[str, NDArray[Any]], order: NDArray[np.intp] | None = None
    ) -> dict[str, NDArray[Any]]:
        """Return ``obs`` with its landmark axes padded to ``M`` and ``landmark_mask`` added.

        Parameters
        ----------
        obs
            The observation of ``N`` landmarks, leading dimensions ``(...)``.
        order
            ``None``: landmark ``n`` in slot ``n``. Else ``(N,)`` or ``(..., N)`` the slot of
            each landmark (:meth:`draw_order`; one row per leading index).
        """
        lead = obs["visible"].shape[:-1]
        if order is not None:
            order = np.broadcast_to(np.asarray(order, dtype=np.intp), (*lead, self.n))
        out: dict[str, NDArray[Any]] = {}
        for key, value in obs.items():
            width = self.PER_LANDMARK.get(key)
            if width is not None:
                padded = np.zeros((*value.shape[:-1], width * self.m), dtype=value.dtype)
                if order is None:
                    padded[..., : width * self.n] = value
                else:
                    columns = order[..., :, None] * width + np.arange(width)
                    np.put_along_axis(padded, columns.reshape(*lead, -1), value, axis=-1)
                out[key] = padded
            elif key == "c_error":
                pairs = self.m * (self.m - 1) // 2
                padded = np.zeros((*value.shape[:-1], pairs), dtype=value.dtype)
                if order is None:
                    padded[..., self.pair_slots] = value
                else:
                    np.put_along_axis(padded, self.pair_index(order), value, axis=-1)
                out[key] = padded
            else:
                out[key] = value
        if order is None:
            out["landmark_mask"] = np.broadcast_to(self.mask, (*lead, self.m)).copy()
        else:
            mask = np.zeros((*lead, self.m), dtype=np.float32)
            np.put_along_axis(mask, order, 1.0, axis=-1)
            out["landmark_mask"] = mask
        return out


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
