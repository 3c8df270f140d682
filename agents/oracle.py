"""The pose oracle: the smooth control law fed the exact poses (the paper's "real 3D parameters").

It needs the env's privileged observation (``gym.make(..., privileged=True)``), which adds the
true ``robot_pose`` and ``goal_pose``. It follows stable-baselines3's ``predict`` interface, so
``evaluate_policy`` runs it like a trained model.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from agents.smooth_control import SmoothControlLaw, ego_polar
from radial_ibvs_gym.physics import RobotConfig

__all__ = ["PoseOracle"]


class PoseOracle:
    """Drive to the goal pose with the smooth control law on the true poses.

    Parameters
    ----------
    law
        The smooth control law (gains, speed limits); its ``v_max`` and ``omega_max`` default to
        the robot's.
    robot
        The robot, for the action scale (``action = (v / v_max, omega / omega_max)``).
    stop_radius
        Within this distance of the goal (metres) the command is zero.
    """

    def __init__(
        self,
        law: SmoothControlLaw | None = None,
        robot: RobotConfig | None = None,
        stop_radius: float = 0.005,
    ) -> None:
        self.robot = robot or RobotConfig()
        self.law = law or SmoothControlLaw(
            v_max=self.robot.max_linear_speed, omega_max=self.robot.max_angular_speed
        )
        self.stop_radius = float(stop_radius)

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
        r, phi, delta = ego_polar(goal_pose.reshape(-1, 3), robot_pose.reshape(-1, 3))
        scale = np.array([self.robot.max_linear_speed, self.robot.max_angular_speed])
        actions = np.zeros((len(r), 2))
        for i in range(len(r)):
            if r[i] > self.stop_radius:
                actions[i] = np.array(self.law.velocity(r[i], phi[i], delta[i])) / scale
        actions = np.clip(actions, -1.0, 1.0).astype(np.float32)
        return (actions if batched else actions[0]), state
