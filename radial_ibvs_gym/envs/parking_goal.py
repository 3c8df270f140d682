"""``RadialIBVS/ParkingGoal-v0``: the parking task as a goal-conditioned env (for SB3's HER)."""

from __future__ import annotations

from typing import Any

import numpy as np
from gymnasium import spaces

from radial_ibvs_gym.envs import logic
from radial_ibvs_gym.envs.parking import ParkingEnv

__all__ = ["ParkingGoalEnv"]


class ParkingGoalEnv(ParkingEnv):
    """The parking task with a goal-conditioned ``Dict`` observation.

    Same dynamics, actions, episode end and arguments as :class:`ParkingEnv`. The observation
    follows Gymnasium-Robotics' ``GoalEnv`` convention, so stable-baselines3's
    ``HerReplayBuffer`` can relabel goals:

    | key | space | meaning |
    |---|---|---|
    | ``observation`` | ``Box(-1, 1, (3N,))`` | current ``x_n`` (flattened), visibility mask |
    | ``achieved_goal`` | ``Box(-1, 1, (2N,))`` | current ``x_n``, flattened (zeros where hidden) |
    | ``desired_goal`` | ``Box(-1, 1, (2N,))`` | goal image ``x_n*``, flattened |

    The step reward is :meth:`compute_reward` (an image-space distance), plus the collision and
    lost-landmark penalties and the success bonus of :class:`ParkingEnv`; ``info`` carries the
    same keys, ``info["is_success"]`` included.
    """

    def __init__(self, *args: Any, goal_reward_power: float = 0.5, **kwargs: Any) -> None:
        kwargs.setdefault("obs_mode", "points")
        if kwargs.get("max_landmarks") is not None:
            raise ValueError("ParkingGoal-v0 does not take max_landmarks yet; use Parking-v0")
        if kwargs["obs_mode"] != "points":
            raise ValueError("ParkingGoal-v0 supports obs_mode='points' only")
        super().__init__(*args, **kwargs)
        if not goal_reward_power > 0:
            raise ValueError(f"goal_reward_power must be positive, got {goal_reward_power!r}")
        self.goal_reward_power = float(goal_reward_power)
        n = self.scenario.n_landmarks
        self.observation_space = spaces.Dict(  # type: ignore[assignment]
            {
                "observation": spaces.Box(-1.0, 1.0, (3 * n,), np.float32),
                "achieved_goal": spaces.Box(-1.0, 1.0, (2 * n,), np.float32),
                "desired_goal": spaces.Box(-1.0, 1.0, (2 * n,), np.float32),
            }
        )

    def compute_reward(
        self, achieved_goal: np.ndarray, desired_goal: np.ndarray, info: Any
    ) -> np.ndarray:
        """Image-space reward ``-(mean |achieved - desired|) ** goal_reward_power``.

        Parameters
        ----------
        achieved_goal, desired_goal
            ``(..., 2N)`` flattened normalised image points (batched for HER).
        info
            Unused (kept for the ``GoalEnv`` signature).

        Returns
        -------
        numpy.ndarray
            ``(...)`` rewards, <= 0, 0 when the images agree.
        """
        diff = np.abs(np.asarray(achieved_goal) - np.asarray(desired_goal))
        return np.asarray(-np.power(diff.mean(axis=-1), self.goal_reward_power))

    def step(
        self, action: np.ndarray
    ) -> tuple[dict[str, np.ndarray], float, bool, bool, dict[str, Any]]:
        """Step as :class:`ParkingEnv`, with the goal-conditioned reward."""
        obs, _, terminated, truncated, info = super().step(action)
        distance = float(self.compute_reward(obs["achieved_goal"], obs["desired_goal"], info))
        terms = logic.goal_reward_terms(info["reward_terms"], distance)
        info["reward_terms"] = terms
        return obs, float(sum(info["reward_terms"].values())), terminated, truncated, info

    def _obs(self) -> dict[str, np.ndarray]:
        assert self._setup is not None
        return logic.goal_observation(
            self._points.reshape(-1), self._visible, self._setup.goal_points.reshape(-1)
        )
