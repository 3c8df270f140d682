"""``RadialIBVS/ParkingGoal-v1``: the goal-conditioned parking task (HER), scalar and batched."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from gymnasium import spaces
from numpy.typing import NDArray

from radial_ibvs_gym.envs import observation as seen
from radial_ibvs_gym.envs import rules
from radial_ibvs_gym.envs.config import ParkingConfig
from radial_ibvs_gym.envs.parking import ParkingEnv
from radial_ibvs_gym.envs.parking_vector import ParkingVectorEnv

__all__ = [
    "GoalConfig",
    "GoalReward",
    "ParkingGoalEnv",
    "ParkingGoalVectorEnv",
    "depth_observation",
    "goal_observation_space",
]


@dataclass(frozen=True)
class GoalConfig:
    """``ParkingGoal-v1``'s own arguments, validated once (beside the shared ``ParkingConfig``).

    Attributes
    ----------
    goal_reward_power
        ``p`` of the reward term ``-D ** p`` (> 0).
    goal_image_tolerance
        ``D`` at or below which the image counts as reached (>= 0, finite).

    Raises
    ------
    ValueError
        For a power that is not positive and finite, or a negative or infinite tolerance.
    """

    goal_reward_power: float = 0.5
    goal_image_tolerance: float = 0.02

    def __post_init__(self) -> None:
        power, tolerance = self.goal_reward_power, self.goal_image_tolerance
        if not (_is_real(power) and math.isfinite(power) and power > 0):
            raise ValueError(f"goal_reward_power must be positive, got {power!r}")
        if not (_is_real(tolerance) and math.isfinite(tolerance) and tolerance >= 0):
            raise ValueError(f"goal_image_tolerance must be finite and >= 0, got {tolerance!r}")
        object.__setattr__(self, "goal_reward_power", float(power))
        object.__setattr__(self, "goal_image_tolerance", float(tolerance))

    @classmethod
    def of(cls, obs_mode: str, **kwargs: float) -> GoalConfig:
        """Validate the goal env's arguments for a ``ParkingConfig``'s ``obs_mode``."""
        if obs_mode != "points":
            raise ValueError("ParkingGoal-v1 supports obs_mode='points' only")
        return cls(**kwargs)


def _is_real(value: Any) -> bool:
    return isinstance(value, int | float | np.integer | np.floating) and not isinstance(value, bool)


def goal_observation_space(config: ParkingConfig) -> spaces.Dict:
    """Return ``ParkingGoal-v1``'s observation space (``M`` entries: the slots or the scene's).

    With ``goal_depths``, each goal is ``(3M,)``: the image points, then the depths (metres).
    """
    m = config.observed_landmarks
    goal = spaces.Box(-1.0, 1.0, (2 * m,), np.float32)
    if config.goal_depths:
        low = np.concatenate([-np.ones(2 * m), np.zeros(m)]).astype(np.float32)
        high = np.concatenate([np.ones(2 * m), np.full(m, 1e3)]).astype(np.float32)
        goal = spaces.Box(low, high, dtype=np.float32)
    return spaces.Dict(
        {
            "observation": spaces.Box(-1.0, 1.0, (3 * m,), np.float32),
            "achieved_goal": goal,
            "desired_goal": goal,
        }
    )


def depth_observation(
    config: ParkingConfig,
    landmarks: NDArray[np.complex128],
    poses: NDArray[np.float64],
    visible: NDArray[np.bool_],
) -> NDArray[np.float64]:
    """Return the depths that would come with an image taken at ``poses`` ``(..., 3)``, metres.

    The horizontal distances ``(..., N)`` of the landmarks ``visible`` ``(..., N)`` there, times
    the scenario's ``depth_scale``, as the goal depths ``d*`` are given; 0 for the hidden ones
    (whose image points are 0 too). What a goal image taken here would come with, so that
    HER's relabelled goals carry depths as the true goals do.
    """
    position = poses[..., 0:1] + 1j * poses[..., 1:2]
    depths = config.scenario.config.depth_scale * np.abs(landmarks - position)
    return np.where(visible, depths, 0.0)


class GoalReward:
    """``ParkingGoal-v1``'s reward, shared by the scalar and the vector env (for HER).

    Reads the env's ``config.weights`` and ``goal_config``; its :meth:`_reward_terms` is the
    envs' reward hook.
    """

    config: ParkingConfig
    #: the goal env's own arguments
    goal_config: GoalConfig
    #: the env's current and goal image points, ``(..., N, 2)`` each (zeros where hidden)
    _images: Callable[[], tuple[np.ndarray, np.ndarray]]
    #: the reward terms (``info["reward_<term>"]``), in the order they are summed
    reward_term_names: tuple[str, ...] = rules.GOAL_REWARD_TERMS

    def reward_terms_of(
        self, achieved_goal: np.ndarray, desired_goal: np.ndarray, info: Any
    ) -> dict[str, np.ndarray]:
        """Return the named terms of :meth:`compute_reward` (a step's ``info["reward_<term>"]``).

        With ``goal_depths``, only the goals' image points count (their first ``2M`` values).
        """
        achieved_goal, desired_goal = self._points_of(achieved_goal, desired_goal)
        return rules.goal_reward_terms(
            achieved_goal,
            desired_goal,
            info,
            self.config.weights,
            self.goal_config.goal_reward_power,
            self.goal_config.goal_image_tolerance,
        )

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

    @property
    def goal_reward_power(self) -> float:
        """``p`` of the reward term ``-D ** p`` (``goal_config``)."""
        return self.goal_config.goal_reward_power

    @property
    def goal_image_tolerance(self) -> float:
        """``D`` at or below which the image counts as reached (``goal_config``)."""
        return self.goal_config.goal_image_tolerance

    def _reward_terms(
        self, previous: Any, now: Any, collision: Any, lost: Any, success: Any
    ) -> dict[str, Any]:
        """Return the step's terms, :meth:`reward_terms_of` its images: the envs' reward hook.

        The pose errors ``previous`` and ``now`` and the pose ``success`` are not read: the
        reward is ``compute_reward(achieved_goal, desired_goal, info)``, as HER needs. The
        image distance ignores empty slots, so the unpadded images give the padded ones' terms.
        """
        points, goal_points = self._images()
        lead = points.shape[:-2]
        achieved = points.reshape(*lead, -1).astype(np.float32)
        desired = goal_points.reshape(*lead, -1).astype(np.float32)
        terms = self.reward_terms_of(achieved, desired, {"collision": collision, "lost": lost})
        return {k: np.asarray(v, dtype=np.float64) for k, v in terms.items()}

    def image_distance(self, achieved_goal: np.ndarray, desired_goal: np.ndarray) -> np.ndarray:
        """``D`` of the goals ``(..., 2M)`` or, with depths, ``(..., 3M)`` (their points only).

        :func:`~radial_ibvs_gym.envs.rules.image_distance`.
        """
        return rules.image_distance(*self._points_of(achieved_goal, desired_goal))

    def _points_of(self, *goals: Any) -> tuple[np.ndarray, ...]:
        """Return the goals' image points (with ``goal_depths``, their first ``2M`` values)."""
        if not self.config.goal_depths:
            return tuple(np.asarray(g) for g in goals)
        points = 2 * self.config.observed_landmarks
        return tuple(np.asarray(g)[..., :points] for g in goals)


class ParkingGoalEnv(GoalReward, ParkingEnv):
    """``RadialIBVS/ParkingGoal-v1``: the goal-conditioned task, all reward in ``compute_reward``.

    Same dynamics, actions, episode end, ``info`` and arguments as :class:`ParkingEnv`. The
    observation follows Gymnasium-Robotics' ``GoalEnv`` convention, so stable-baselines3's
    ``HerReplayBuffer`` can relabel goals (``M`` landmark entries: the scene's, or the
    ``max_landmarks`` slots, so one model runs in every scene of at most ``M`` landmarks):

    | key | space | meaning |
    |---|---|---|
    | ``observation`` | ``Box(-1, 1, (3M,))`` | current ``x_n`` (flattened), visibility mask |
    | ``achieved_goal`` | ``Box(-1, 1, (2M,))`` | current ``x_n``, flattened (zeros where hidden) |
    | ``desired_goal`` | ``Box(-1, 1, (2M,))`` | goal image ``x_n*``, flattened |

    With ``goal_depths=True`` each goal also carries its depths, ``(3M,)``: ``desired_goal`` the
    goal depths ``d*`` after the goal image, ``achieved_goal`` the depths a goal image taken at the
    current pose would come with (the visible landmarks' horizontal distances, times the scenario's
    ``depth_scale``; 0 for the hidden ones), so a relabelled goal has depths as a true one does; the
    reward reads the image points only. What a policy that solves the goal's pose from the bearings
    needs (``radial_ibvs_agents.learned.networks.extractors.GoalPoseExtractor``, which reads only
    the desired goal's depths). Those current depths are ranges a camera alone does not measure: a
    policy that reads all of ``achieved_goal`` (SB3's ``MultiInputPolicy`` does) is given them.

    **The step reward equals** ``compute_reward(achieved_goal, desired_goal, info)``, the
    ``GoalEnv`` rule that HER relies on (:func:`~radial_ibvs_gym.envs.rules.goal_reward_terms`).
    The terms are ``image_distance = -D ** p`` (``D`` the mean absolute difference of the image
    coordinates of the landmarks seen in either image, ``p = goal_reward_power``), ``collision
    = -collision_penalty`` and ``lost = -lost_penalty`` (read from ``info["collision"]`` and
    ``info["lost"]``, so relabelled transitions keep them), and ``success = success_bonus`` when
    ``D <= goal_image_tolerance`` (success in the image, which a relabelled goal has too).

    ## Version History
    - v1: every reward term inside ``compute_reward``; ``max_landmarks`` taken.
    - v0 (removed before the first release): the collision, lost and success terms were
      added outside ``compute_reward``, so HER's relabelled transitions lost them.

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

    _own_arguments = ("goal_reward_power", "goal_image_tolerance")

    def __init__(
        self,
        *args: Any,
        goal_reward_power: float = 0.5,
        goal_image_tolerance: float = 0.02,
        **kwargs: Any,
    ) -> None:
        kwargs.setdefault("obs_mode", "points")
        self.goal_config = GoalConfig.of(
            kwargs["obs_mode"],
            goal_reward_power=goal_reward_power,
            goal_image_tolerance=goal_image_tolerance,
        )
        super().__init__(*args, **kwargs)
        self.observation_space = goal_observation_space(self.config)  # type: ignore[assignment]

    def _obs(self) -> dict[str, np.ndarray]:
        assert self._setup is not None
        obs: dict[str, np.ndarray] = {
            "points": self._points.reshape(-1),
            "visible": np.asarray(self._visible, dtype=np.float32),
            "goal_points": self._setup.goal_points.reshape(-1),
        }
        if self.config.goal_depths:
            pose = self.world.pose if self.world is not None else self._setup.episode.start
            obs["depths"] = depth_observation(
                self.config, self._setup.landmarks_c, pose, self._visible
            )
            obs["goal_depths"] = self._setup.goal_depths
        if self.slots is not None:
            obs = self.slots.pad(obs, self._setup.slot_order, self._setup.present)
        return seen.goal_observation(
            obs["points"], obs["visible"], obs["goal_points"], obs.get("depths"),
            obs.get("goal_depths"),
        )  # fmt: skip


class ParkingGoalVectorEnv(GoalReward, ParkingVectorEnv):
    """``RadialIBVS/ParkingGoal-v1`` for ``num_envs`` robots (all reward in ``compute_reward``).

    Same as :class:`ParkingVectorEnv` with the observation and reward of
    :class:`~radial_ibvs_gym.envs.parking_goal.ParkingGoalEnv`: the step reward of each
    robot equals ``compute_reward(achieved_goal, desired_goal, info)`` for its row. Takes
    ``goal_reward_power`` and ``goal_image_tolerance`` as the scalar env does.
    """

    _own_arguments = ("goal_reward_power", "goal_image_tolerance")

    def __init__(
        self,
        num_envs: int = 1,
        *,
        goal_reward_power: float = 0.5,
        goal_image_tolerance: float = 0.02,
        **kwargs: Any,
    ) -> None:
        kwargs.setdefault("obs_mode", "points")
        self.goal_config = GoalConfig.of(
            kwargs["obs_mode"],
            goal_reward_power=goal_reward_power,
            goal_image_tolerance=goal_image_tolerance,
        )
        super().__init__(num_envs, **kwargs)

    def _single_observation_space(self) -> spaces.Space[Any]:
        return goal_observation_space(self.config)

    def _observation(self, idx: Any = slice(None)) -> dict[str, NDArray[Any]]:
        points, batch = self._points[idx], self.batch
        n = len(points)
        obs = {
            "points": points.reshape(n, -1),
            "visible": self._visible[idx].astype(np.float32),
            "goal_points": batch.goal_points[idx].reshape(n, -1),
        }
        t = self.config
        if t.goal_depths:
            landmarks, poses = batch.landmarks_c[idx], self.fleet.poses[idx]
            obs["depths"] = depth_observation(t, landmarks, poses, self._visible[idx])
            obs["goal_depths"] = batch.goal_depths[idx]
        if t.slots is not None:
            order = batch.slot_orders[idx] if t.slot_order == "random" else None
            obs = t.slots.pad(obs, order, None if batch.present.all() else batch.present[idx])
        return seen.goal_observation(
            obs["points"], obs["visible"], obs["goal_points"], obs.get("depths"),
            obs.get("goal_depths"),
        )  # fmt: skip
