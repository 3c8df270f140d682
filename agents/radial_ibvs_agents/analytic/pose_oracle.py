"""The pose oracle: the smooth control law fed the exact poses (the paper's "real 3D parameters").

It needs the env's privileged observation (``gym.make(..., privileged=True)``), which adds the
true ``robot_pose`` and ``goal_pose``. It follows stable-baselines3's ``predict`` interface, so
``evaluate_policy`` runs it like a trained model.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from radial_ibvs_agents.analytic.ibvs_maths import park_command
from radial_ibvs_agents.analytic.ibvs_maths_batch import park_command_batch
from radial_ibvs_agents.analytic.smooth_control import SmoothControlLaw, ego_polar
from radial_ibvs_gym.geometry import pose_in_frame, wrap_angle
from radial_ibvs_gym.physics import RobotConfig

__all__ = ["PoseOracle"]


class PoseOracle:
    """Drive to the goal pose with the smooth control law on the true poses.

    By default the speed follows the paper's mapping, as the IBVS does: the virtual target is the
    true goal in the robot frame, ``v_l = lam r``, ``omega = kappa v_l`` (eq. 38), speed limits
    scaling both (:func:`radial_ibvs_agents.analytic.ibvs_maths.robot_command`), so the oracle and
    the IBVS differ only in where ``r, phi, delta`` come from (the paper's "real 3D parameters"
    comparison). With ``law`` set, the speeds come from that :class:`SmoothControlLaw` instead
    (nav2's speed-from-curvature rule).

    Parameters
    ----------
    lam
        Gain of the paper's mapping ``v_l = lam r``, 1/s.
    k1, k2
        Gains of eq. (38).
    robot
        The robot, for the speed limits and the action scale
        (``action = (v / v_max, omega / omega_max)``).
    stop_radius, stop_heading
        Zero command within this distance of the goal (metres) when the heading error is also
        below ``stop_heading`` (radians).
    rotate_radius
        Within this distance of the goal (metres), the final approach of
        :func:`radial_ibvs_agents.analytic.ibvs_maths.park_command` (drive the forward part, turn to
        the goal heading).
    law
        Optional nav2-style speed law (its ``v_max``/``omega_max`` should be the robot's).
    allow_backward
        Drive backwards when the goal is behind the robot (nav2's ``allow_backward``); the
        paper's law drives forwards only (the default).
    """

    #: how it runs in a batch of episodes (:mod:`radial_ibvs_agents.rollouts`): one ``predict`` for
    #: every robot, each robot's action as alone
    batch_mode = "batch"

    def __init__(
        self,
        lam: float = 0.5,
        k1: float = 4.0,
        k2: float = 12.0,
        robot: RobotConfig | None = None,
        stop_radius: float = 0.002,
        stop_heading: float = math.radians(0.1),
        rotate_radius: float = 0.02,
        law: SmoothControlLaw | None = None,
        allow_backward: bool = False,
    ) -> None:
        for name, value in (("lam", lam), ("k1", k1), ("k2", k2)):
            if not (math.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be finite and positive, got {value!r}")
        self.lam, self.k1, self.k2 = float(lam), float(k1), float(k2)
        self.robot = robot or RobotConfig()
        self.stop_radius, self.stop_heading = float(stop_radius), float(stop_heading)
        self.rotate_radius = float(rotate_radius)
        self.law = law
        self.allow_backward = bool(allow_backward)

    def __repr__(self) -> str:
        backward = ", allow_backward=True" if self.allow_backward else ""
        return f"PoseOracle(lam={self.lam}, k1={self.k1}, k2={self.k2}, law={self.law!r}{backward})"

    @property
    def env_kwargs(self) -> dict[str, bool]:
        """What ``gym.make`` must add to the observation: the true poses."""
        return {"privileged": True}

    def predict(
        self,
        observation: dict[str, np.ndarray],
        state: Any = None,
        episode_start: np.ndarray | None = None,
        deterministic: bool = True,
    ) -> tuple[np.ndarray, Any]:
        """Action(s) for one observation or a batch, as stable-baselines3's ``predict``.

        Parameters
        ----------
        observation
            The env's privileged ``Dict`` observation, unbatched (``robot_pose`` of shape
            ``(3,)``) or batched (``(B, 3)``).
        state, episode_start, deterministic
            Unused (the oracle is stateless and deterministic); kept for the interface.

        Returns
        -------
        tuple
            ``(action, state)``: ``action`` of shape ``(2,)`` or ``(B, 2)``, float32 in
            ``[-1, 1]``.

        Raises
        ------
        KeyError
            If the observation lacks the true poses (the env was not made with
            ``privileged=True``).
        """
        if "robot_pose" not in observation or "goal_pose" not in observation:
            raise KeyError("PoseOracle needs the true poses: make the env with privileged=True")
        robot_pose = np.asarray(observation["robot_pose"], dtype=np.float64)
        goal_pose = np.asarray(observation["goal_pose"], dtype=np.float64)
        batched = robot_pose.ndim == 2
        robots, goals = robot_pose.reshape(-1, 3), goal_pose.reshape(-1, 3)
        actions = np.array([self.act(p, g) for p, g in zip(robots, goals, strict=True)])
        actions = np.clip(actions, -1.0, 1.0).astype(np.float32).reshape(-1, 2)
        return (actions if batched else actions[0]), state

    def act_from_origin(self, goals: np.ndarray) -> np.ndarray:
        """Return the actions ``(B, 2)`` towards goals ``(B, 3)`` given in the robot's frame.

        :meth:`act` with ``pose`` at the origin, for a batch (eq. 38 batched,
        :func:`~radial_ibvs_agents.analytic.ibvs_maths_batch.park_command_batch`; one robot at a
        time with a ``law``). Metres and radians in, ``(v / v_max, omega / omega_max)`` out, not
        clipped.
        """
        goals = np.asarray(goals, dtype=np.float64).reshape(-1, 3)
        if self.law is not None:
            origin = np.zeros(3)
            return np.array([self.act(origin, g) for g in goals], dtype=np.float64).reshape(-1, 2)
        v_max, w_max = self.robot.max_linear_speed, self.robot.max_angular_speed
        v, omega = park_command_batch(
            self.lam * goals[:, :2], wrap_angle(goals[:, 2]), self.lam, self.k1, self.k2,
            v_max, w_max, self.stop_radius, self.stop_heading, self.rotate_radius,
            self.allow_backward,
        )  # fmt: skip
        return np.stack([v / v_max, omega / w_max], axis=-1)

    def act(self, pose: np.ndarray, goal: np.ndarray) -> tuple[float, float]:
        """Return the action ``(v / v_max, omega / omega_max)`` from ``pose`` to ``goal``.

        ``pose`` and ``goal`` are ``(x, y, yaw)`` in one frame (metres, radians): the world
        (the oracle), or the robot's own with ``pose`` at the origin (a pose estimated from
        the image: :class:`radial_ibvs_agents.analytic.pbvs.PBVSPolicy`). Not clipped.
        """
        v_max, w_max = self.robot.max_linear_speed, self.robot.max_angular_speed
        x, y, gamma = pose_in_frame(pose, goal)  # the goal in the robot frame
        target = np.array([x, y])
        if self.law is not None:
            r = math.hypot(goal[0] - pose[0], goal[1] - pose[1])
            if r < self.stop_radius and abs(gamma) < self.stop_heading:
                return 0.0, 0.0
            reverse = self.allow_backward and target[0] < 0.0  # the goal is behind
            rr, phi, delta = ego_polar(goal, pose, backward=reverse)
            v, omega = self.law.velocity(float(rr), float(phi), float(delta), backward=reverse)
        else:
            v, omega = park_command(
                self.lam * target, gamma, self.lam, self.k1, self.k2, v_max, w_max,
                self.stop_radius, self.stop_heading, self.rotate_radius, self.allow_backward,
            )  # fmt: skip
        return v / v_max, omega / w_max
