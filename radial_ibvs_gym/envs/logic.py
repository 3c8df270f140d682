"""The parking task's logic, batched: observation, errors, reward terms and episode end.

One implementation serves the scalar envs (:class:`~radial_ibvs_gym.envs.parking.ParkingEnv`,
no batch dimension) and the native vector env
(:class:`~radial_ibvs_gym.envs.parking_vector.ParkingVectorEnv`, a leading ``(B,)`` batch of
envs): every function is elementwise over leading dimensions, so the two cannot drift apart.
Pure numpy; frames and units as everywhere (world frame, metres, radians).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from radial_ibvs_gym.camera import CatadioptricCamera, Imperfections, normalise_pixels
from radial_ibvs_gym.camera.batch import forward_batch, shares_reflection
from radial_ibvs_gym.features import c_ij, virtual_point_weights
from radial_ibvs_gym.geometry import wrap_angle
from radial_ibvs_gym.limits import MAX_LANDMARKS

__all__ = [
    "ACTION_RULE",
    "IMPERFECTION_KEYS",
    "REWARD_TERMS",
    "Slots",
    "camera_image",
    "camera_images",
    "episode_end",
    "feature_errors",
    "goal_weights",
    "imperfections_info",
    "pose_errors",
    "potential",
    "radial_image",
    "reward_terms",
    "unit_or_dummy",
]

_TWO_PI = 2.0 * math.pi

#: the reward terms, in the order they are summed (``info["reward_terms"]``)
REWARD_TERMS = ("progress", "heading", "precision", "time", "collision", "lost", "success")

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
    position = pose[..., :2].view(np.complex128)  # (..., 1): x + i y, no copy
    turn = np.exp(-1j * pose[..., 2:3])  # the world -> camera rotation about the axis
    w = (landmarks - position) * turn
    rho = np.abs(w)
    visible = (rho > radius_lo) & (rho < radius_hi)
    w *= visible / np.maximum(rho, 1e-300)
    return w.view(np.float64).reshape(*w.shape, 2), visible


def camera_image(
    camera: CatadioptricCamera, p_cam: Array, rng: np.random.Generator
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
        The env's generator (pixel noise).

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
    rngs: Sequence[np.random.Generator],
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
        ``K`` generators (pixel noise).

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
) -> tuple[Any, Any, Any]:
    """Success, lost and termination of a step (bools, or ``(B,)`` bool arrays).

    Success: both errors within the tolerances. Lost: fewer than ``min_visible`` landmarks
    visible. Termination: success, lost, or a collision when ``terminate_on_collision``.
    """
    success = (position_error <= success_position_m) & (heading_error <= success_heading_rad)
    lost = n_visible < min_visible
    terminated = success | lost
    if terminate_on_collision:
        terminated = terminated | collision
    return success, lost, terminated


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
    points: Array, visible: NDArray[np.bool_], goal_points: Array
) -> dict[str, NDArray[np.float32]]:
    """Build the ``ParkingGoal-v0`` observation dict (goal-conditioned, for HER).

    ``points``, ``goal_points``: ``(..., 2N)`` flattened image points; ``visible``: ``(..., N)``.
    """
    achieved = np.asarray(points, dtype=np.float32)
    return {
        "observation": np.concatenate([achieved, np.asarray(visible, dtype=np.float32)], axis=-1),
        "achieved_goal": achieved,
        "desired_goal": np.asarray(goal_points, dtype=np.float32),
    }


def goal_reward_terms(terms: Mapping[str, Any], image_distance: Any) -> dict[str, Any]:
    """``ParkingGoal-v0``'s terms: the image distance reward, the events; no shaping terms."""
    out = {k: v for k, v in terms.items() if k not in ("progress", "heading", "precision", "time")}
    out["image_distance"] = image_distance
    return out


#: the one rule for actions, in the scalar and the vector envs alike
ACTION_RULE = "two finite numbers (values outside [-1, 1] are clipped to it)"

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
