"""Position-based visual servoing: the goal's pose solved from the image, then a law on the pose.

Image-only, like the IBVS (no map, no true pose): each landmark seen now and in the goal image
constrains the goal's planar pose linearly, and :func:`solve_goal_pose` solves those constraints
jointly in closed form (least squares, the same solve as the first layer of the ``dagger-student``,
:func:`radial_ibvs_agents.learned.networks.pose_layer.solve_goal_pose`, here in numpy:
:func:`radial_ibvs_gym.geometry.bearing_pose.solve_goal_pose`, whose docstring states the
constraints). The pose then drives the paper's smooth law (eq. 38) as the pose oracle does with the
true poses: :class:`PBVSPolicy` is Fig. 3's "exact 3D parameters" replaced by the image's estimate.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from radial_ibvs_agents.analytic.pose_oracle import PoseOracle
from radial_ibvs_gym.geometry.bearing_pose import solve_goal_pose

__all__ = ["PBVSPolicy", "solve_goal_pose"]


class PBVSPolicy:
    """Position-based visual servoing: the smooth law (eq. 38) on the pose solved from the image.

    Reads the current and goal image points and the goal depths (as the IBVS does), solves the
    goal's pose (:func:`solve_goal_pose`) and drives the pose oracle's law with it
    (:class:`~radial_ibvs_agents.analytic.pose_oracle.PoseOracle`: the paper's mapping
    ``v_l = lam r``, eq. 38, the final approach within ``rotate_radius``). With fewer than three
    landmarks seen in both images, or no unique pose, the command is zero.

    Parameters
    ----------
    **oracle_kwargs
        The law's settings, as :class:`~radial_ibvs_agents.analytic.pose_oracle.PoseOracle` takes
        them (``lam``, ``k1``, ``k2``, ``robot``, ``stop_radius``, ``rotate_radius``,
        ``allow_backward``...).
    """

    #: how it runs in a batch of episodes (:mod:`radial_ibvs_agents.rollouts`): one ``predict`` for
    #: every robot, each robot's action as alone
    batch_mode = "batch"

    def __init__(self, **oracle_kwargs: Any) -> None:
        self.law = PoseOracle(**oracle_kwargs)

    def __repr__(self) -> str:
        return f"PBVSPolicy({self.law!r})"

    @property
    def env_kwargs(self) -> dict[str, bool]:
        """What ``gym.make`` must add to the observation: the goal depths ``d*``."""
        return {"goal_depths": True}

    def _as_batch(self, observation: dict[str, np.ndarray]) -> tuple[dict[str, Any], bool]:
        """Return the observation with a leading batch axis, and whether it had one.

        Raises
        ------
        KeyError
            If the observation lacks ``goal_depths`` (make the env with ``goal_depths=True``).
        """
        if "goal_depths" not in observation:
            raise KeyError(
                f"{type(self).__name__} needs observation['goal_depths']: make the env with "
                f"{self.env_kwargs}"
            )
        batched = np.ndim(observation["points"]) == 2
        obs = observation if batched else {k: np.asarray(v)[None] for k, v in observation.items()}
        return obs, batched

    def goal_pose(self, observation: dict[str, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
        """Return ``(x, y, theta)`` of the goal in the robot's frame, ``(B, 3)``, and validity.

        Metres and radians; ``observation`` batched (``points`` ``(B, 2N)``).
        """
        points = np.asarray(observation["points"], dtype=np.float64)
        b = len(points)
        now = points.reshape(b, -1, 2)
        goal = np.asarray(observation["goal_points"], dtype=np.float64).reshape(b, -1, 2)
        seen = (np.linalg.norm(goal, axis=-1) > 0.5) & (np.asarray(observation["visible"]) > 0.5)
        depth = np.asarray(observation["goal_depths"], dtype=np.float64).reshape(b, -1)
        pose, valid = solve_goal_pose(now, goal, depth, seen)
        theta = np.arctan2(pose[:, 3], pose[:, 2])
        return np.stack([pose[:, 0], pose[:, 1], theta], axis=-1), valid

    def predict(
        self,
        observation: dict[str, np.ndarray],
        state: Any = None,
        episode_start: np.ndarray | None = None,
        deterministic: bool = True,
    ) -> tuple[np.ndarray, Any]:
        """Action(s) for one observation or a batch, as stable-baselines3's ``predict``.

        Returns
        -------
        tuple
            ``(action, state)``: ``(2,)`` or ``(B, 2)`` float32 in ``[-1, 1]``; ``state``
            unused (the policy is stateless).

        Raises
        ------
        KeyError
            If the observation lacks ``goal_depths`` (make the env with ``goal_depths=True``).
        """
        obs, batched = self._as_batch(observation)
        targets, valid = self.goal_pose(obs)
        actions = np.zeros((len(targets), 2))
        if valid.any():
            actions[valid] = self.law.act_from_origin(targets[valid])
        actions = np.clip(actions, -1.0, 1.0).astype(np.float32)
        return (actions if batched else actions[0]), state
