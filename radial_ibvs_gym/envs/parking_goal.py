"""``RadialIBVS/ParkingGoal-v0`` and ``-v1``: the parking task as a goal-conditioned env (HER)."""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np
from gymnasium import spaces

from radial_ibvs_gym.envs import logic
from radial_ibvs_gym.envs.parking import ParkingEnv

__all__ = ["ParkingGoalEnv", "ParkingGoalEnvV1"]


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

    .. deprecated:: 0.2.0
        The penalties and the bonus are outside :meth:`compute_reward`, so HER's relabelled
        transitions never see them, and ``max_landmarks`` is refused. Use
        ``RadialIBVS/ParkingGoal-v1`` (:class:`ParkingGoalEnvV1`); v0 keeps its behaviour
        and warns (``DeprecationWarning``) when made.
    """

    def __init__(self, *args: Any, goal_reward_power: float = 0.5, **kwargs: Any) -> None:
        if type(self) is ParkingGoalEnv:
            warnings.warn(
                "RadialIBVS/ParkingGoal-v0 is deprecated: its collision, lost and success terms "
                "are outside compute_reward, so HER's relabelled transitions miss them; use "
                "RadialIBVS/ParkingGoal-v1",
                DeprecationWarning,
                stacklevel=2,
            )
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


def _flags(info: Any, key: str, shape: tuple[int, ...]) -> np.ndarray:
    """``info[key]`` as a float array of ``shape``, for one info or a batch of them.

    ``info`` is one step's dict (a bool), a vector env's dict (an array), or a sequence of
    dicts, as stable-baselines3's ``HerReplayBuffer`` passes them (one per relabelled step).
    """
    if isinstance(info, dict):
        value = np.asarray(info.get(key, False), dtype=np.float64)
    elif info is None:
        value = np.zeros(shape)
    else:
        value = np.array([bool(i.get(key, False)) for i in np.ravel(info)], dtype=np.float64)
    try:
        return np.broadcast_to(value.reshape(value.shape or ()), shape)
    except ValueError:
        raise ValueError(
            f"info[{key!r}] has {value.size} value(s) for {int(np.prod(shape))} goal(s)"
        ) from None


class ParkingGoalEnvV1(ParkingGoalEnv):
    """``RadialIBVS/ParkingGoal-v1``: the goal-conditioned task, all reward in ``compute_reward``.

    As :class:`ParkingGoalEnv` (v0), with two changes:

    - **The step reward equals** ``compute_reward(achieved_goal, desired_goal, info)``, the
      ``GoalEnv`` rule that HER relies on. The terms are ``image_distance = -D ** p`` (``D`` the
      mean absolute difference of the image coordinates of the landmarks seen in either
      image, ``p = goal_reward_power``), ``collision = -collision_penalty`` and ``lost =
      -lost_penalty`` (read from ``info["collision"]`` and ``info["lost"]``, so relabelled
      transitions keep them), and ``success = success_bonus`` when ``D <=
      goal_image_tolerance`` (success in the image, which a relabelled goal has too).
      In v0 the collision, lost and success terms were added outside ``compute_reward``,
      so relabelled transitions lost them: a crash ended the negative rewards for free.
    - **It takes** ``max_landmarks``: ``observation`` ``Box(-1, 1, (3M,))`` (the current points
      and the visibility, padded to ``M`` slots), ``achieved_goal`` and ``desired_goal``
      ``Box(-1, 1, (2M,))``, so one model runs in every scene of at most ``M`` landmarks.

    Parameters
    ----------
    goal_reward_power
        ``p`` (> 0).
    goal_image_tolerance
        ``D`` at or below which the image counts as reached (>= 0). The default, 0.02, is
        about what a pose error of 2 cm and 2 deg gives in the ``random`` rooms (median
        0.022 over 200 rooms; a 2 deg turn moves every point by 0.035 on the unit circle).
    **kwargs
        :class:`~radial_ibvs_gym.envs.parking.ParkingEnv`'s arguments (``obs_mode="points"``).
    """

    def __init__(
        self,
        *args: Any,
        goal_reward_power: float = 0.5,
        goal_image_tolerance: float = 0.02,
        **kwargs: Any,
    ) -> None:
        kwargs.setdefault("obs_mode", "points")
        if kwargs["obs_mode"] != "points":
            raise ValueError("ParkingGoal-v1 supports obs_mode='points' only")
        ParkingEnv.__init__(self, *args, **kwargs)
        if not (math.isfinite(goal_reward_power) and goal_reward_power > 0):
            raise ValueError(f"goal_reward_power must be positive, got {goal_reward_power!r}")
        if not (math.isfinite(goal_image_tolerance) and goal_image_tolerance >= 0):
            raise ValueError(
                f"goal_image_tolerance must be finite and >= 0, got {goal_image_tolerance!r}"
            )
        self.goal_reward_power = float(goal_reward_power)
        self.goal_image_tolerance = float(goal_image_tolerance)
        m = self.scenario.n_landmarks if self.slots is None else self.slots.m
        self.observation_space = spaces.Dict(  # type: ignore[assignment]
            {
                "observation": spaces.Box(-1.0, 1.0, (3 * m,), np.float32),
                "achieved_goal": spaces.Box(-1.0, 1.0, (2 * m,), np.float32),
                "desired_goal": spaces.Box(-1.0, 1.0, (2 * m,), np.float32),
            }
        )

    def image_distance(self, achieved_goal: np.ndarray, desired_goal: np.ndarray) -> np.ndarray:
        """``D``: the mean absolute coordinate difference over the landmarks in either image.

        Parameters
        ----------
        achieved_goal, desired_goal
            ``(..., 2M)`` flattened normalised image points (zeros where hidden).

        Returns
        -------
        numpy.ndarray
            ``(...)``, >= 0 (0 where no landmark is seen in either image).
        """
        a = np.asarray(achieved_goal, dtype=np.float64)
        d = np.asarray(desired_goal, dtype=np.float64)
        a, d = a.reshape(*a.shape[:-1], -1, 2), d.reshape(*d.shape[:-1], -1, 2)
        used = (np.hypot(a[..., 0], a[..., 1]) > 0.5) | (np.hypot(d[..., 0], d[..., 1]) > 0.5)
        total = np.sum(np.abs(a - d).sum(axis=-1) * used, axis=-1)
        return total / np.maximum(2.0 * used.sum(axis=-1), 1.0)

    def reward_terms_of(
        self, achieved_goal: np.ndarray, desired_goal: np.ndarray, info: Any
    ) -> dict[str, np.ndarray]:
        """Return the named terms of :meth:`compute_reward` (a step's ``info["reward_terms"]``)."""
        distance = self.image_distance(achieved_goal, desired_goal)
        w = self.weights
        return {
            "image_distance": -np.power(distance, self.goal_reward_power),
            "collision": -w["collision_penalty"] * _flags(info, "collision", distance.shape),
            "lost": -w["lost_penalty"] * _flags(info, "lost", distance.shape),
            "success": w["success_bonus"] * (distance <= self.goal_image_tolerance),
        }

    def compute_reward(
        self, achieved_goal: np.ndarray, desired_goal: np.ndarray, info: Any
    ) -> np.ndarray:
        """Return the step reward for (batched) goals: the sum of :meth:`reward_terms_of`.

        Parameters
        ----------
        achieved_goal, desired_goal
            ``(..., 2M)`` flattened normalised image points (batched for HER).
        info
            The step's ``info`` (``collision`` and ``lost`` are read), a vector env's batched
            ``info``, or a sequence of per-step ``info`` dicts (HER); ``None`` counts no
            collision and no loss.

        Returns
        -------
        numpy.ndarray
            ``(...)`` rewards.
        """
        terms = self.reward_terms_of(achieved_goal, desired_goal, info)
        return np.asarray(sum(terms.values()))

    def step(
        self, action: np.ndarray
    ) -> tuple[dict[str, np.ndarray], float, bool, bool, dict[str, Any]]:
        """Step as :class:`ParkingEnv`; the reward is :meth:`compute_reward` of the step."""
        obs, _, terminated, truncated, info = ParkingEnv.step(self, action)
        terms = self.reward_terms_of(obs["achieved_goal"], obs["desired_goal"], info)
        info["reward_terms"] = {k: float(v) for k, v in terms.items()}
        reward = sum(info["reward_terms"].values())  # = compute_reward of the step (tested)
        return obs, reward, terminated, truncated, info

    def _obs(self) -> dict[str, np.ndarray]:
        assert self._setup is not None
        obs: dict[str, np.ndarray] = {
            "points": self._points.reshape(-1),
            "visible": np.asarray(self._visible, dtype=np.float32),
            "goal_points": self._setup.goal_points.reshape(-1),
        }
        if self.slots is not None:
            obs = self.slots.pad(obs, self._setup.slot_order)
        return logic.goal_observation(obs["points"], obs["visible"], obs["goal_points"])
