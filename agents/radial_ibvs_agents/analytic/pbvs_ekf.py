"""``pbvs-ekf``: position-based servoing on the goal's pose filtered by an extended Kalman filter.

The state is the goal's planar pose in the robot's frame, ``s = (x, y, theta)`` (metres,
radians; x forward, y left), with its covariance ``P``, per robot.

- **Initialisation**: the first frame where the image gives a pose
  (:func:`~radial_ibvs_agents.analytic. pbvs.solve_goal_pose`) sets ``s`` to it and
  ``P = diag(init_std_m^2, init_std_m^2, init_std_rad^2)``.
- **Prediction**, each control period ``dt``: the robot moves by the twist it commanded,
  through the robot's speed and acceleration limits (what the env applies,
  :func:`radial_ibvs_gym.physics.limit_command`) and the exact unicycle over ``dt``
  (:func:`radial_ibvs_gym.physics.integrate_unicycle`); the goal, fixed in the world, moves
  the other way in the robot's frame. ``F`` is that map's Jacobian, and the process noise
  ``Q = diag(q_xy, q_xy, q_theta)`` with ``q_xy = (motion_std * |v| dt + f)^2`` and
  ``q_theta = (motion_std * |omega| dt + f)^2``, ``f = motion_floor`` (1e-4 m, rad): a
  relative error ``motion_std`` of the motion (wheel slip, the pymunk contacts).
- **Update**: the bearing ``beta_n = atan2(q_y, q_x)`` of each landmark seen now and in the
  goal image, with ``q_n = R(theta) p_n + t`` and ``p_n = d*_n x*_n`` the landmark in the
  goal's frame (from the goal image and the goal depths, as the IBVS uses them); the
  residual wrapped to ``(-pi, pi]``; measurement noise ``bearing_std`` per landmark (about one
  pixel at 100 pixels from the image centre). The camera's radial model makes the bearing of
  a normalised image point the landmark's azimuth, so this is the camera's own measurement
  model.

The law on the filtered pose is the pose oracle's (eq. 38), as in
:class:`~radial_ibvs_agents.analytic. pbvs.PBVSPolicy`. With no pose yet (fewer than three landmarks
seen at the start), the command is zero.
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple

import numpy as np

from radial_ibvs_agents.analytic.pbvs import PBVSPolicy
from radial_ibvs_gym.geometry import wrap_angle
from radial_ibvs_gym.physics.fleet import limit_commands

__all__ = ["Filters", "PBVSEKFPolicy", "executed_actions"]


def executed_actions(executed: Any, batch: int) -> np.ndarray:
    """Return ``executed`` commands as ``(batch, 2)`` actions, clipped to ``[-1, 1]``.

    Raises
    ------
    ValueError
        For another shape or a value that is not finite.
    """
    moved = np.asarray(executed, dtype=np.float64).reshape(-1, 2)
    if moved.shape != (batch, 2) or not np.isfinite(moved).all():
        raise ValueError(
            f"executed must be {batch} finite (v, omega) action rows, got {np.shape(executed)}"
        )
    return np.clip(moved, -1.0, 1.0)


class PBVSEKFPolicy(PBVSPolicy):
    """PBVS on the goal pose filtered over time by an extended Kalman filter (module docs).

    Parameters
    ----------
    control_dt
        The env's control period, seconds (``control_dt``, 0.1 by default).
    bearing_std
        Standard deviation of a measured bearing, radians.
    motion_std
        Relative standard deviation of the robot's motion over a period.
    init_std_m, init_std_rad
        Standard deviations of the first pose solved from the image, metres and radians.
    motion_floor
        The process noise's floor per period, metres and radians: how far the filter lets
        the pose wander between frames when the robot stands still.
    **oracle_kwargs
        The law's settings (:class:`~radial_ibvs_agents.analytic.pose_oracle.PoseOracle`).

    Notes
    -----
    ``state`` (``predict``'s second value, :class:`Filters`) holds, per robot, the filter's
    mean, covariance, last applied velocity and whether it has started; pass it back at the
    next step, with ``episode_start`` true at a reset. Every robot of a batch is filtered at
    once (the same maths for one robot or many).
    """

    def __init__(
        self,
        control_dt: float = 0.1,
        bearing_std: float = 0.01,
        motion_std: float = 0.05,
        init_std_m: float = 0.05,
        init_std_rad: float = 0.02,
        motion_floor: float = 1e-4,
        **oracle_kwargs: Any,
    ) -> None:
        super().__init__(**oracle_kwargs)
        for name, value in (
            ("motion_floor", motion_floor),
            ("control_dt", control_dt),
            ("bearing_std", bearing_std),
            ("motion_std", motion_std),
            ("init_std_m", init_std_m),
            ("init_std_rad", init_std_rad),
        ):
            if not (math.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be finite and positive, got {value!r}")
        self.control_dt, self.bearing_std, self.motion_std = control_dt, bearing_std, motion_std
        self.motion_floor = float(motion_floor)
        self.init_cov = np.diag([init_std_m**2, init_std_m**2, init_std_rad**2])

    def __repr__(self) -> str:
        return f"PBVSEKFPolicy(bearing_std={self.bearing_std}, motion_std={self.motion_std})"

    def predict(
        self,
        observation: dict[str, np.ndarray],
        state: Any = None,
        episode_start: np.ndarray | None = None,
        deterministic: bool = True,
        *,
        executed: np.ndarray | None = None,
    ) -> tuple[np.ndarray, Any]:
        """Action(s) for one observation or a batch; ``state`` carries the filters (see Notes).

        Parameters
        ----------
        executed
            ``(2,)`` or ``(B, 2)``: the command the robot will execute until the next frame,
            in action units, when it is not this policy's own (a replay of a robot driven
            by something else, ``radial-ibvs replay --motion recorded``); the filter predicts
            the motion from it. ``None``: from the action returned.

        Returns
        -------
        tuple
            ``(action, state)``: ``(2,)`` or ``(B, 2)`` float32 in ``[-1, 1]``, the filters.
        """
        obs, batched = self._as_batch(observation)
        b = len(obs["points"])
        filters = state if isinstance(state, Filters) and len(state.started) == b else None
        if filters is None:
            filters = Filters.empty(b)
        starts = np.ones(b, dtype=bool) if episode_start is None else np.asarray(episode_start)
        starts = np.broadcast_to(starts.astype(bool).reshape(-1), (b,))
        mean, cov, velocity, started, _, _ = self._filter(obs, filters, starts)
        actions = np.zeros((b, 2))
        if started.any():
            actions[started] = self.law.act_from_origin(mean[started])
        actions = np.clip(actions, -1.0, 1.0)
        moved = actions if executed is None else executed_actions(executed, b)
        mean, cov, velocity = self._predict(mean, cov, velocity, moved, started)
        out = actions.astype(np.float32)
        return (out if batched else out[0]), Filters(mean, cov, velocity, started)

    def _filter(
        self, obs: dict[str, np.ndarray], filters: Filters, starts: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Correct the filters with this frame; start those whose first pose it gives.

        Returns the mean, covariance, velocity and started flags after the frame (robots at
        ``starts`` begin afresh), and the pose solved from the frame alone with its validity.
        """
        started = filters.started & ~starts
        mean, cov = self._update(filters.mean.copy(), filters.cov.copy(), obs, started)
        solved, valid = self.goal_pose(obs)
        new = ~started & valid  # the first pose solved from the image starts the filter
        mean[new], cov[new] = solved[new], self.init_cov
        velocity = np.where(new[:, None], 0.0, filters.velocity)
        return mean, cov, velocity, started | new, solved, valid

    @staticmethod
    def select_state(state: Filters, rows: np.ndarray) -> Filters:
        """Return the filters of the robots at positions ``rows`` of the batch."""
        return Filters(*(np.asarray(part)[rows] for part in state))

    def _predict(
        self,
        mean: np.ndarray,
        cov: np.ndarray,
        velocity: np.ndarray,
        action: np.ndarray,
        started: np.ndarray,
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Move the goals by the robots' motion over one period (the commands, limited)."""
        robot, dt = self.law.robot, self.control_dt
        command = action * np.array([robot.max_linear_speed, robot.max_angular_speed])
        applied = limit_commands(command, velocity, dt, robot)
        v, omega = applied[:, 0], applied[:, 1]
        # the robot's move in its old frame: the exact unicycle (integrate_unicycle), batched
        half = 0.5 * omega * dt
        small = np.abs(half) <= 1e-12
        sinc = np.where(small, 1.0 - half * half / 6.0, np.sin(half) / np.where(small, 1.0, half))
        chord = v * dt * sinc
        mx, my, myaw = chord * np.cos(half), chord * np.sin(half), wrap_angle(omega * dt)
        # the goal in the robot's new frame (pose_in_frame), and that map's Jacobian
        c, s = np.cos(myaw), np.sin(myaw)
        dx, dy = mean[:, 0] - mx, mean[:, 1] - my
        moved = np.stack([c * dx + s * dy, -s * dx + c * dy, wrap_angle(mean[:, 2] - myaw)], -1)
        zero, one = np.zeros_like(c), np.ones_like(c)
        jacobian = np.stack(
            [
                np.stack([c, s, zero], -1),
                np.stack([-s, c, zero], -1),
                np.stack([zero, zero, one], -1),
            ],
            axis=-2,
        )
        floor = self.motion_floor
        q_xy = (self.motion_std * np.abs(v) * dt + floor) ** 2
        q_theta = (self.motion_std * np.abs(omega) * dt + floor) ** 2
        noise = np.zeros_like(cov)
        noise[:, 0, 0], noise[:, 1, 1], noise[:, 2, 2] = q_xy, q_xy, q_theta
        predicted = jacobian @ cov @ np.swapaxes(jacobian, -1, -2) + noise
        keep = started[:, None]
        return (
            np.where(keep, moved, mean),
            np.where(keep[..., None], predicted, cov),
            np.where(keep, applied, velocity),
        )

    def _update(
        self, mean: np.ndarray, cov: np.ndarray, obs: dict[str, np.ndarray], rows: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """Correct the poses of ``rows`` with the bearings of the landmarks seen now and at goal.

        A landmark not seen gets a zero row in the measurement Jacobian and a zero residual: it
        changes nothing, and every robot's update is one fixed-size solve.
        """
        b = len(mean)
        now = np.asarray(obs["points"], dtype=np.float64).reshape(b, -1, 2)
        goal = np.asarray(obs["goal_points"], dtype=np.float64).reshape(b, -1, 2)
        seen = (np.linalg.norm(goal, axis=-1) > 0.5) & (np.asarray(obs["visible"]) > 0.5)
        seen &= rows[:, None]
        if not seen.any():
            return mean, cov
        depth = np.asarray(obs["goal_depths"], dtype=np.float64).reshape(b, -1)
        p = depth[..., None] * goal  # (B, M, 2), the landmarks in the goal's frame
        x, y, theta = mean[:, 0:1], mean[:, 1:2], mean[:, 2:3]
        c, s = np.cos(theta), np.sin(theta)
        qx, qy = c * p[..., 0] - s * p[..., 1] + x, s * p[..., 0] + c * p[..., 1] + y
        r2 = np.maximum(qx * qx + qy * qy, 1e-12)
        predicted = np.arctan2(qy, qx)
        measured = np.arctan2(now[..., 1], now[..., 0])
        residual = np.where(seen, np.angle(np.exp(1j * (measured - predicted))), 0.0)
        dq_x, dq_y = -s * p[..., 0] - c * p[..., 1], c * p[..., 0] - s * p[..., 1]
        db_x, db_y = -qy / r2, qx / r2
        h = np.stack([db_x, db_y, db_x * dq_x + db_y * dq_y], axis=-1) * seen[..., None]
        m = h.shape[1]
        innovation = h @ cov @ np.swapaxes(h, -1, -2) + self.bearing_std**2 * np.eye(m)
        gain = np.swapaxes(np.linalg.solve(innovation, h @ cov), -1, -2)  # (B, 3, M)
        corrected = mean + (gain @ residual[..., None])[..., 0]
        corrected[:, 2] = np.arctan2(np.sin(corrected[:, 2]), np.cos(corrected[:, 2]))
        updated = (np.eye(3) - gain @ h) @ cov
        keep = seen.any(axis=1)
        return np.where(keep[:, None], corrected, mean), np.where(keep[:, None, None], updated, cov)


class Filters(NamedTuple):
    """The filters of a batch of robots (``PBVSEKFPolicy.predict``'s state).

    Attributes
    ----------
    mean
        ``(B, 3)`` the goal's pose in each robot's frame, metres and radians.
    cov
        ``(B, 3, 3)`` its covariance.
    velocity
        ``(B, 2)`` the velocity each robot applied last, m/s and rad/s.
    started
        ``(B,)`` whether each robot's filter has a pose yet.
    """

    mean: np.ndarray
    cov: np.ndarray
    velocity: np.ndarray
    started: np.ndarray

    @classmethod
    def empty(cls, b: int) -> Filters:
        """Return ``b`` filters that have not started."""
        return cls(np.zeros((b, 3)), np.zeros((b, 3, 3)), np.zeros((b, 2)), np.zeros(b, bool))
