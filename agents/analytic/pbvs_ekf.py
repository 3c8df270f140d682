"""``pbvs-ekf``: position-based servoing on the goal's pose filtered by an extended Kalman filter.

The state is the goal's planar pose in the robot's frame, ``s = (x, y, theta)`` (metres,
radians; x forward, y left), with its covariance ``P``, per robot.

- **Initialisation**: the first frame where the image gives a pose (:func:`~agents.analytic.
  pbvs.solve_goal_pose`) sets ``s`` to it and ``P = diag(init_std_m^2, init_std_m^2,
  init_std_rad^2)``.
- **Prediction**, each control period ``dt``: the robot moves by the twist it commanded,
  through the robot's speed and acceleration limits (what the env applies,
  :func:`radial_ibvs_gym.physics.limit_command`) and the exact unicycle over ``dt``
  (:func:`radial_ibvs_gym.physics.integrate_unicycle`); the goal, fixed in the world, moves
  the other way in the robot's frame. ``F`` is that map's Jacobian, and the process noise
  ``Q = diag(q_xy, q_xy, q_theta)`` with ``q_xy = (motion_std * |v| dt + 1e-4)^2`` and
  ``q_theta = (motion_std * |omega| dt + 1e-4)^2``: a relative error ``motion_std`` of the
  motion (wheel slip, the pymunk contacts).
- **Update**: the bearing ``beta_n = atan2(q_y, q_x)`` of each landmark seen now and in the
  goal image, with ``q_n = R(theta) p_n + t`` and ``p_n = d*_n x*_n`` the landmark in the
  goal's frame (from the goal image and the goal depths, as the IBVS uses them); the
  residual wrapped to ``(-pi, pi]``; measurement noise ``bearing_std`` per landmark (about one
  pixel at 100 pixels from the image centre). The camera's radial model makes the bearing of
  a normalised image point the landmark's azimuth, so this is the camera's own measurement
  model.

The law on the filtered pose is the pose oracle's (eq. 38), as in :class:`~agents.analytic.
pbvs.PBVSPolicy`. With no pose yet (fewer than three landmarks seen at the start), the
command is zero.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from agents.analytic.pbvs import PBVSPolicy
from radial_ibvs_gym.geometry import pose_in_frame
from radial_ibvs_gym.physics import integrate_unicycle, limit_command

__all__ = ["PBVSEKFPolicy"]


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
    **oracle_kwargs
        The law's settings (:class:`~agents.analytic.pose_oracle.PoseOracle`).

    Notes
    -----
    ``state`` (``predict``'s second value) holds, per robot, the filter's mean, covariance,
    last applied velocity and whether it has started; pass it back at the next step, with
    ``episode_start`` true at a reset.
    """

    def __init__(
        self,
        control_dt: float = 0.1,
        bearing_std: float = 0.01,
        motion_std: float = 0.05,
        init_std_m: float = 0.05,
        init_std_rad: float = 0.02,
        **oracle_kwargs: Any,
    ) -> None:
        super().__init__(**oracle_kwargs)
        for name, value in (
            ("control_dt", control_dt),
            ("bearing_std", bearing_std),
            ("motion_std", motion_std),
            ("init_std_m", init_std_m),
            ("init_std_rad", init_std_rad),
        ):
            if not (math.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be finite and positive, got {value!r}")
        self.control_dt, self.bearing_std, self.motion_std = control_dt, bearing_std, motion_std
        self.init_cov = np.diag([init_std_m**2, init_std_m**2, init_std_rad**2])

    def __repr__(self) -> str:
        return f"PBVSEKFPolicy(bearing_std={self.bearing_std}, motion_std={self.motion_std})"

    def predict(
        self,
        observation: dict[str, np.ndarray],
        state: Any = None,
        episode_start: np.ndarray | None = None,
        deterministic: bool = True,
    ) -> tuple[np.ndarray, Any]:
        """Action(s) for one observation or a batch; ``state`` carries the filters (see Notes).

        Returns
        -------
        tuple
            ``(action, state)``: ``(2,)`` or ``(B, 2)`` float32 in ``[-1, 1]``, the filters.
        """
        obs, batched = self._as_batch(observation)
        b = len(obs["points"])
        filters = state if state is not None else [None] * b
        starts = np.ones(b, dtype=bool) if episode_start is None else np.asarray(episode_start)
        if starts.shape != (b,):
            starts = np.broadcast_to(starts, (b,))
        solved, valid = self.goal_pose(obs)
        actions = np.zeros((b, 2))
        new_filters = []
        for i in range(b):
            f = None if starts[i] else filters[i]
            if f is None and valid[i]:
                f = {"mean": solved[i].copy(), "cov": self.init_cov.copy(), "velocity": np.zeros(2)}
            elif f is not None:
                self._update(f, {k: v[i] for k, v in obs.items()})
            if f is not None:
                actions[i] = np.clip(self.law.act(np.zeros(3), f["mean"]), -1.0, 1.0)
                self._predict(f, actions[i])
            new_filters.append(f)
        out = actions.astype(np.float32)
        return (out if batched else out[0]), new_filters

    @staticmethod
    def select_state(state: list[Any], rows: np.ndarray) -> list[Any]:
        """Return the filters of the robots at positions ``rows`` of the batch."""
        return [state[int(i)] for i in rows]

    def _predict(self, f: dict[str, Any], action: np.ndarray) -> None:
        """Move the goal by the robot's motion over one period (the command, limited)."""
        robot = self.law.robot
        dt = self.control_dt
        command = action * np.array([robot.max_linear_speed, robot.max_angular_speed])
        velocity = limit_command(command, f["velocity"], dt, robot)
        v, omega = float(velocity[0]), float(velocity[1])
        moved = integrate_unicycle(np.zeros(3), v, omega, dt)  # the robot, in its old frame
        mean = np.array(pose_in_frame(moved, f["mean"]))
        c, s = math.cos(moved[2]), math.sin(moved[2])
        jacobian = np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])
        q_xy = (self.motion_std * abs(v) * dt + 1e-4) ** 2
        q_theta = (self.motion_std * abs(omega) * dt + 1e-4) ** 2
        f["cov"] = jacobian @ f["cov"] @ jacobian.T + np.diag([q_xy, q_xy, q_theta])
        f["mean"], f["velocity"] = mean, velocity

    def _update(self, f: dict[str, Any], obs: dict[str, np.ndarray]) -> None:
        """Correct the pose with the bearings of the landmarks seen now and at the goal."""
        now = np.asarray(obs["points"], dtype=np.float64).reshape(-1, 2)
        goal = np.asarray(obs["goal_points"], dtype=np.float64).reshape(-1, 2)
        seen = (np.linalg.norm(goal, axis=-1) > 0.5) & (np.asarray(obs["visible"]) > 0.5)
        if not seen.any():
            return
        depth = np.asarray(obs["goal_depths"], dtype=np.float64).reshape(-1)[seen]
        p = depth[:, None] * goal[seen]
        x, y, theta = f["mean"]
        c, s = math.cos(theta), math.sin(theta)
        q = np.stack([c * p[:, 0] - s * p[:, 1] + x, s * p[:, 0] + c * p[:, 1] + y], axis=-1)
        r2 = np.maximum((q**2).sum(axis=-1), 1e-12)
        predicted = np.arctan2(q[:, 1], q[:, 0])
        measured = np.arctan2(now[seen, 1], now[seen, 0])
        residual = np.angle(np.exp(1j * (measured - predicted)))
        dq_dtheta = np.stack([-s * p[:, 0] - c * p[:, 1], c * p[:, 0] - s * p[:, 1]], axis=-1)
        dbeta_dq = np.stack([-q[:, 1], q[:, 0]], axis=-1) / r2[:, None]
        h = np.concatenate([dbeta_dq, (dbeta_dq * dq_dtheta).sum(axis=-1)[:, None]], axis=-1)
        innovation = h @ f["cov"] @ h.T + self.bearing_std**2 * np.eye(len(h))
        gain = np.linalg.solve(innovation, h @ f["cov"]).T
        mean = f["mean"] + gain @ residual
        mean[2] = math.atan2(math.sin(mean[2]), math.cos(mean[2]))
        f["mean"] = mean
        f["cov"] = (np.eye(3) - gain @ h) @ f["cov"]
