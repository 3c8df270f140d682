"""``ekf-planner``: the planner's path, driven on the filtered pose and a map read from the images.

Image-only, like ``pbvs-ekf`` (no true pose, no map): the goal's pose in the robot's frame is
filtered by ``pbvs-ekf``'s extended Kalman filter, and the room is read from the goal image. The
landmarks hang on the walls, and the goal image with the goal depths places each one in the
goal's frame (``p_n = d*_n x*_n``, as the filter uses them), so the rectangle they lie on is
the room, or less of it where a wall shows no landmark at the goal (:func:`room_frame`).
In that room the planner (:class:`~radial_ibvs_agents.analytic.planner.MapPlanner`: the straight
segment where its turning disc is free, else OMPL) plans the path and follows it
turn-drive-turn on the filtered pose. Turning in place and driving straight keeps the robot
inside the room, where the pose law's curves (``pbvs-ekf``) meet its walls.

Within ``law_radius`` of the goal it hands over to ``pbvs-ekf``'s law (eq. 38 on the filtered
pose), which brings the heading round with the position. Then, as a robot parking by camera
does, it can **stop and look** (``look_steps`` > 0): within ``look_radius`` it stands still for
``look_steps`` control periods and averages the goal's pose solved from each frame. Near the
goal heading that solve is unbiased by the camera's calibration error (the goal image went
through the same camera), and the average beats the pixel noise; the filter restarts from it.
If the averaged pose is within ``park_radius`` and ``park_heading`` the robot stays (and looks
again every ``look_steps`` periods); else it corrects turn-drive-turn with the planner on the
filter (odometry and bearings) and looks again, at most ``max_looks`` times, then goes back to
the law. Each look costs ``look_steps * control_dt`` seconds.

OMPL is optional: ``pip install 'radial_ibvs_gym[planning]'``.
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from radial_ibvs_agents.analytic.pbvs_ekf import Filters, PBVSEKFPolicy, executed_actions
from radial_ibvs_agents.analytic.planner import MapPlanner, Plan

__all__ = [
    "CORRECT",
    "LAW",
    "LOOK",
    "PARKED",
    "PATH",
    "EKFPlanner",
    "EKFPlannerState",
    "RoomFrame",
    "room_frame",
]

F64 = NDArray[np.float64]

#: the side of the room assumed where the goal image places fewer than three landmarks, metres
OPEN_ROOM_M = 200.0


class RoomFrame(NamedTuple):
    """A rectangular room estimated in the goal's frame, and the map frame it defines.

    Attributes
    ----------
    centre
        ``(2,)`` the room's centre in the goal's frame, metres.
    angle
        The direction of the room's first side in the goal's frame, radians.
    size
        ``(2,)`` the room's sides, metres: along ``angle``, then across.
    """

    centre: F64
    angle: float
    size: F64

    def to_map(self, pose: F64) -> F64:
        """Return a pose ``(x, y, yaw)`` of the goal's frame in the map frame.

        The map frame puts the room at ``[0, size[0]] x [0, size[1]]`` (the planner's rooms).
        """
        c, s = math.cos(self.angle), math.sin(self.angle)
        dx, dy = float(pose[0]) - self.centre[0], float(pose[1]) - self.centre[1]
        yaw = math.remainder(float(pose[2]) - self.angle, 2.0 * math.pi)
        return np.array(
            [c * dx + s * dy + 0.5 * self.size[0], -s * dx + c * dy + 0.5 * self.size[1], yaw]
        )

    def observation(self, goal_in_robot: F64) -> dict[str, F64]:
        """Return the planner's observation of one robot: its pose and the goal's, map frame.

        Parameters
        ----------
        goal_in_robot
            ``(3,)`` the goal's pose in the robot's frame (the filter's mean), metres, radians.
        """
        x, y, theta = (float(v) for v in goal_in_robot)
        c, s = math.cos(theta), math.sin(theta)
        robot = np.array([-(c * x + s * y), s * x - c * y, -theta])  # the inverse pose
        return {
            "robot_pose": self.to_map(robot),
            "goal_pose": self.to_map(np.zeros(3)),
            "room": np.asarray(self.size, dtype=np.float64),
            "obstacles": np.zeros((1, 3)),
            "landmarks": np.zeros((1, 3)),
            "landmark_range": np.zeros((1, 2)),
        }


def room_frame(points: F64) -> RoomFrame:
    """Return the rectangle whose sides the landmarks ``(N, 2)`` lie on (metres, any frame).

    The landmarks hang on the room's walls, so in the room's own directions each lies on a side
    of their bounding box. Each direction of a pair of landmarks (two on one wall give the
    room's) is tried; the one whose bounding box has the landmarks nearest its sides (the sum
    of squared distances) wins, and of those equally near, the one more pairs lie along (two
    or more landmarks on a wall). Two landmarks on each wall fix the room; fewer can leave
    another rectangle as good, and a wall without a landmark leaves a rectangle inside the
    room. Fewer than three points give an open room (:data:`OPEN_ROOM_M` a side, centred on
    the goal).
    """
    p = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    if len(p) < 3:
        return RoomFrame(np.zeros(2), 0.0, np.full(2, OPEN_ROOM_M))
    i, j = np.triu_indices(len(p), 1)
    d = p[j] - p[i]
    angles = np.mod(np.arctan2(d[:, 1], d[:, 0]), 0.5 * math.pi)
    c, s = np.cos(angles)[:, None], np.sin(angles)[:, None]
    u = c * p[:, 0] + s * p[:, 1]  # (A, N): the points along each direction and across it
    v = -s * p[:, 0] + c * p[:, 1]
    lo_u, hi_u = u.min(1, keepdims=True), u.max(1, keepdims=True)
    lo_v, hi_v = v.min(1, keepdims=True), v.max(1, keepdims=True)
    gaps = np.minimum(np.minimum(u - lo_u, hi_u - u), np.minimum(v - lo_v, hi_v - v))
    residual = np.sum(gaps**2, axis=1)
    apart = np.abs(np.angle(np.exp(4j * (angles[:, None] - angles[None, :])))) / 4.0
    votes = np.sum(apart < 0.01, axis=1)  # the pairs along each direction (mod 90 deg)
    near = residual <= residual.min() + 1e-6 * max(1.0, float(np.ptp(p)) ** 2)
    k = int(np.flatnonzero(near)[np.argmax(votes[near])])
    mu, mv = 0.5 * (lo_u[k, 0] + hi_u[k, 0]), 0.5 * (lo_v[k, 0] + hi_v[k, 0])
    ck, sk = float(c[k, 0]), float(s[k, 0])
    centre = np.array([ck * mu - sk * mv, sk * mu + ck * mv])
    size = np.array([hi_u[k, 0] - lo_u[k, 0], hi_v[k, 0] - lo_v[k, 0]])
    return RoomFrame(centre, float(angles[k]), size)


class EKFPlannerState(NamedTuple):
    """The state of a batch of ``ekf-planner`` robots (``predict``'s second value).

    Attributes
    ----------
    filters
        The filters of the goal's pose (:class:`~radial_ibvs_agents.analytic.pbvs_ekf.Filters`).
    rooms
        Per robot, the room read from its goal image (``None`` before the filter starts).
    plans
        Per robot, the planner's plan (``None`` before a plan).
    phase
        ``(B,)`` each robot's phase: :data:`PATH`, :data:`LAW`, :data:`LOOK`, :data:`CORRECT`
        or :data:`PARKED`.
    left
        ``(B,)`` control periods left to look (:data:`LOOK`) or to stay (:data:`PARKED`).
    sums
        ``(B, 4)`` the poses solved while looking: sums of ``x``, ``y``, ``cos``, ``sin``.
    counts
        ``(B,)`` how many frames gave a pose while looking.
    looks
        ``(B,)`` how many looks each robot has made this episode.
    """

    filters: Filters
    rooms: list[RoomFrame | None]
    plans: list[Plan | None]
    phase: NDArray[np.int64]
    left: NDArray[np.int64]
    sums: F64
    counts: NDArray[np.int64]
    looks: NDArray[np.int64]

    @classmethod
    def empty(cls, b: int) -> EKFPlannerState:
        """Return the state of ``b`` robots before their first frame."""
        zeros = np.zeros(b, dtype=np.int64)
        return cls(
            Filters.empty(b), [None] * b, [None] * b, zeros, zeros, np.zeros((b, 4)), zeros, zeros
        )


#: the phases of a robot (:attr:`EKFPlannerState.phase`)
PATH, LAW, LOOK, CORRECT, PARKED = range(5)


class EKFPlanner(PBVSEKFPolicy):
    """The planner's path on ``pbvs-ekf``'s filtered pose, in a room read from the goal image.

    Parameters
    ----------
    control_dt, bearing_std, motion_std, init_std_m, init_std_rad, motion_floor
        The filter's settings (:class:`~radial_ibvs_agents.analytic.pbvs_ekf.PBVSEKFPolicy`).
    law_radius
        Hand over to the law once the filtered goal lies this close, metres (latched).
    look_radius
        Stop and look once the filtered goal lies this close, metres; the k-th look of an
        episode (from 0) waits for ``look_radius / 2**k``.
    look_steps
        Control periods to stand still and average per look (0: never look).
    park_radius, park_heading
        A look that finds the goal within these (metres, radians) ends the moves.
    max_looks
        Looks (and corrections) per episode, at most.
    correct
        After a look that does not find the goal within the park tolerances: correct
        turn-drive-turn (``True``), or hand back to the law (``False``).
    law_kwargs
        The law's settings (:class:`~radial_ibvs_agents.analytic.pose_oracle.PoseOracle`).
    **planner_kwargs
        The planner's settings (:class:`~radial_ibvs_agents.analytic.planner.MapPlanner`:
        ``margin``, ``gain``, ``goal_tolerance``, near-goal rules...). It keeps no landmark in
        view (the heights are not in the image points): ``min_visible`` is 0.

    Raises
    ------
    ValueError
        If OMPL is not installed (the message names the extra), or for a bad setting.
    """

    #: one ``predict`` for the whole batch: the filters step together, the plans robot by robot
    batch_mode = "batch"

    def __init__(
        self,
        control_dt: float = 0.1,
        bearing_std: float = 0.01,
        motion_std: float = 0.05,
        init_std_m: float = 0.05,
        init_std_rad: float = 0.02,
        motion_floor: float = 1e-4,
        law_radius: float = 1.0,
        look_radius: float = 0.05,
        look_steps: int = 0,
        park_radius: float = 0.005,
        park_heading: float = math.radians(0.5),
        max_looks: int = 4,
        correct: bool = True,
        law_kwargs: dict[str, Any] | None = None,
        **planner_kwargs: Any,
    ) -> None:
        super().__init__(
            control_dt,
            bearing_std,
            motion_std,
            init_std_m,
            init_std_rad,
            motion_floor,
            **(law_kwargs or {}),
        )
        for name, value in (
            ("law_radius", law_radius),
            ("look_radius", look_radius),
            ("park_radius", park_radius),
            ("park_heading", park_heading),
        ):
            if isinstance(value, bool) or not (math.isfinite(value) and value >= 0):
                raise ValueError(f"{name} must be finite and >= 0, got {value!r}")
        for name, count in (("look_steps", look_steps), ("max_looks", max_looks)):
            if isinstance(count, bool) or not isinstance(count, int) or count < 0:
                raise ValueError(f"{name} must be an integer >= 0, got {count!r}")
        self.law_radius, self.look_radius = float(law_radius), float(look_radius)
        self.look_steps, self.max_looks = look_steps, max_looks
        self.park_radius, self.park_heading = float(park_radius), float(park_heading)
        self.correct = bool(correct)
        self.planner = MapPlanner(min_visible=0, **planner_kwargs)
        #: the corrections after a look: turn to the point however near (no ``hold_radius``),
        #: forwards or backwards
        self.corrector = MapPlanner(
            min_visible=0, **{**planner_kwargs, "hold_radius": 0.0, "reverse": True}
        )

    def __repr__(self) -> str:
        return (
            f"EKFPlanner(law_radius={self.law_radius}, look_radius={self.look_radius}, "
            f"look_steps={self.look_steps})"
        )

    @staticmethod
    def select_state(  # type: ignore[override]  # the filters and the plans: its own state
        state: EKFPlannerState, rows: np.ndarray
    ) -> EKFPlannerState:
        """Return the state of the robots at positions ``rows`` of the batch."""
        picked = np.asarray(rows).reshape(-1).tolist()
        return EKFPlannerState(
            PBVSEKFPolicy.select_state(state.filters, rows),
            [state.rooms[i] for i in picked],
            [state.plans[i] for i in picked],
            *(np.asarray(part)[rows] for part in state[3:]),
        )

    def predict(
        self,
        observation: dict[str, np.ndarray],
        state: Any = None,
        episode_start: np.ndarray | None = None,
        deterministic: bool = True,
        *,
        executed: np.ndarray | None = None,
    ) -> tuple[np.ndarray, Any]:
        """Action(s) for one observation or a batch; ``state`` an :class:`EKFPlannerState`.

        ``executed``: the command the robot executes until the next frame, when not this
        policy's own (:meth:`PBVSEKFPolicy.predict`).

        Returns
        -------
        tuple
            ``(action, state)``: ``(2,)`` or ``(B, 2)`` float32 in ``[-1, 1]``, and the state
            to pass back with ``episode_start`` true at a reset.
        """
        obs, batched = self._as_batch(observation)
        b = len(obs["points"])
        if not (isinstance(state, EKFPlannerState) and len(state.rooms) == b):
            state = EKFPlannerState.empty(b)
        starts = np.ones(b, dtype=bool) if episode_start is None else np.asarray(episode_start)
        starts = np.broadcast_to(starts.astype(bool).reshape(-1), (b,))
        fresh = EKFPlannerState.empty(b)
        rooms, plans = list(state.rooms), list(state.plans)
        phase, left, sums, counts, looks = (
            np.where(starts.reshape(-1, *[1] * (np.ndim(part) - 1)), new, part).copy()
            for part, new in zip(state[3:], fresh[3:], strict=True)
        )
        for i in np.flatnonzero(starts).tolist():
            rooms[i], plans[i] = None, None
        mean, cov, velocity, started, solved, valid = self._filter(obs, state.filters, starts)
        actions = np.zeros((b, 2))
        by_law: list[int] = []  # the robots the law drives: one batched call after the loop
        for i in np.flatnonzero(started).tolist():
            if rooms[i] is None:
                rooms[i] = room_frame(self._landmarks(obs, i))
            distance = math.hypot(*mean[i, :2])
            if phase[i] == PATH and distance < self.law_radius:
                phase[i] = LAW  # latched: no switching back and forth at the radius
            if (
                phase[i] == LAW
                and self.look_steps
                and looks[i] < self.max_looks
                and distance < self.look_radius / 2 ** looks[i]
            ):
                phase[i], left[i], sums[i], counts[i] = LOOK, self.look_steps, 0.0, 0
            if phase[i] == LOOK:
                if np.abs(velocity[i]).max() > 0.0:
                    continue  # still slowing down: the frames of a moving robot differ
                if valid[i]:
                    x, y, theta = solved[i]
                    sums[i] += (x, y, math.cos(theta), math.sin(theta))
                    counts[i] += 1
                left[i] -= 1
                if left[i] <= 0:
                    self._looked(i, mean, cov, phase, left, sums, counts, looks, plans)
                continue  # standing still
            if phase[i] == PARKED:
                left[i] -= 1
                if left[i] <= 0:
                    phase[i], left[i], sums[i], counts[i] = LOOK, self.look_steps, 0.0, 0
                continue
            if phase[i] == LAW:
                by_law.append(i)
                continue
            row = rooms[i].observation(mean[i])
            fresh_plan = np.array([plans[i] is None])
            planner = self.corrector if phase[i] == CORRECT else self.planner
            action, planned = planner.predict(row, [plans[i]], episode_start=fresh_plan)
            plans[i] = planned[0]
            actions[i] = action
            done = planned[0].index >= len(planned[0].waypoints)
            if phase[i] == CORRECT and done and abs(mean[i, 2]) < self.park_heading:
                phase[i], left[i], sums[i], counts[i] = LOOK, self.look_steps, 0.0, 0
                actions[i] = 0.0
        if by_law:  # eq. (38) row by row: each robot's action has the bits it has alone
            actions[by_law] = self.law.act_from_origin(mean[by_law])
        actions = np.clip(actions, -1.0, 1.0)
        moved = actions if executed is None else executed_actions(executed, b)
        mean, cov, velocity = self._predict(mean, cov, velocity, moved, started)
        out = actions.astype(np.float32)
        filters = Filters(mean, cov, velocity, started)
        state = EKFPlannerState(filters, rooms, plans, phase, left, sums, counts, looks)
        return (out if batched else out[0]), state

    def _looked(
        self,
        i: int,
        mean: F64,
        cov: F64,
        phase: NDArray[np.int64],
        left: NDArray[np.int64],
        sums: F64,
        counts: NDArray[np.int64],
        looks: NDArray[np.int64],
        plans: list[Plan | None],
    ) -> None:
        """End robot ``i``'s look: restart its filter from the average, then park or correct."""
        looks[i] += 1
        if counts[i]:
            x, y, c, s = sums[i] / counts[i]
            mean[i] = (x, y, math.atan2(s, c))
            cov[i] = self.init_cov / counts[i]
        near = math.hypot(*mean[i, :2]) <= self.park_radius
        if near and abs(mean[i, 2]) <= self.park_heading:
            phase[i], left[i] = PARKED, self.look_steps
        elif looks[i] > self.max_looks or not self.correct:
            phase[i] = LAW
        else:
            phase[i], plans[i] = CORRECT, None

    @staticmethod
    def _landmarks(obs: dict[str, Any], i: int) -> F64:
        """Robot ``i``'s landmarks seen in the goal image, in the goal's frame ``(K, 2)``."""
        goal = np.asarray(obs["goal_points"][i], dtype=np.float64).reshape(-1, 2)
        depth = np.asarray(obs["goal_depths"][i], dtype=np.float64).reshape(-1)
        seen = np.linalg.norm(goal, axis=-1) > 0.5
        return depth[seen, None] * goal[seen]
