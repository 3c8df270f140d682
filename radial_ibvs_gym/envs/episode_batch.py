"""The episodes of ``N`` envs as ``(N, ...)`` arrays, for the native vector env.

:class:`EpisodeBatch` holds, row by row, what each env's
:class:`~radial_ibvs_gym.envs.episodes.EpisodeSetup` holds that a batched step reads (the
landmarks, the goal and its image, the drawn slots and imperfections), and the feature errors'
state (:class:`~radial_ibvs_gym.envs.feature_errors.FeatureErrors`). :meth:`EpisodeBatch.put`
is the one place a drawn episode becomes a row.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from radial_ibvs_gym.envs import rules
from radial_ibvs_gym.envs.config import ParkingConfig
from radial_ibvs_gym.envs.episodes import EpisodeSetup
from radial_ibvs_gym.envs.feature_errors import FeatureErrors
from radial_ibvs_gym.envs.rules import IMPERFECTION_KEYS

__all__ = ["EpisodeBatch"]


class EpisodeBatch:
    """The current episode of each of ``n`` envs, as ``(n, ...)`` arrays (metres, radians).

    Parameters
    ----------
    config
        The envs' arguments (the scene's ``N`` landmarks, the observation mode).
    n
        The envs.

    Attributes
    ----------
    setups
        Each env's :class:`~radial_ibvs_gym.envs.episodes.EpisodeSetup` (``None`` before its
        first reset): its cameras, missed detections and map.
    landmarks_c
        ``(n, N)`` the landmarks on the floor plane, complex ``x + i y``.
    landmarks_w
        ``(n, N, 3)`` the landmarks in the world frame (the imperfect camera's input).
    present
        ``(n, N)`` which landmarks each episode has (a drawn landmark count leaves the rest
        absent: never visible).
    camera_heights
        ``(n,)`` each episode's camera height, metres.
    bounds
        ``(2, n, N)`` the current camera's visible interval of horizontal distances (an ideal
        camera's; zeros for a camera with imperfections).
    goals, privileged_goals
        ``(n, 3)`` the goal poses, and those the privileged observation shows.
    tasks
        ``(n,)`` the task indices.
    goal_points, goal_visible, goal_depths
        ``(n, N, 2)``, ``(n, N)`` and ``(n, N)``: the goal image and its depths ``d*``.
    slot_orders
        ``(n, N)`` the slots of the landmarks (``slot_order="random"``).
    imperfections
        ``(n, K)`` the drawn imperfections, columns as ``rules.IMPERFECTION_KEYS``.
    features
        The feature errors' state (``obs_mode="features"``), else ``None``.
    """

    def __init__(self, config: ParkingConfig, n: int) -> None:
        nl = config.scenario.n_landmarks
        self.setups: list[EpisodeSetup | None] = [None] * n
        self.landmarks_c = np.zeros((n, nl), dtype=np.complex128)
        self.landmarks_w = np.zeros((n, nl, 3))
        self.present = np.ones((n, nl), dtype=bool)
        self.camera_heights = np.zeros(n)
        self.bounds = np.zeros((2, n, nl))
        self.goals = np.zeros((n, 3))
        self.privileged_goals = np.zeros((n, 3))
        self.tasks = np.zeros(n, dtype=np.int64)
        self.goal_points = np.zeros((n, nl, 2))
        self.goal_visible = np.zeros((n, nl), dtype=bool)
        self.goal_depths = np.zeros((n, nl))
        self.slot_orders = np.zeros((n, nl), dtype=np.intp)
        self.imperfections = np.zeros((n, len(IMPERFECTION_KEYS)))
        self.features = (
            FeatureErrors(n, nl, config.pairs) if config.obs_mode == "features" else None
        )

    def put(self, i: int, setup: EpisodeSetup) -> None:
        """Make ``setup`` the episode of env ``i``."""
        episode = setup.episode
        self.setups[i] = setup
        self.landmarks_c[i] = setup.landmarks_c
        self.landmarks_w[i] = setup.points_w
        self.present[i] = True if setup.present is None else setup.present
        self.camera_heights[i] = episode.camera_height
        bounds = setup.radius_bounds["current"]
        if bounds is not None:
            self.bounds[0, i], self.bounds[1, i] = bounds
        self.goals[i] = episode.goal
        self.privileged_goals[i] = setup.privileged_goal
        self.tasks[i] = episode.task
        self.goal_points[i] = setup.goal_points
        self.goal_visible[i] = setup.goal_visible
        self.goal_depths[i] = setup.goal_depths
        if setup.slot_order is not None:
            self.slot_orders[i] = setup.slot_order
        if setup.imperfections is not None:
            drawn = rules.imperfections_info(setup.imperfections)
            self.imperfections[i] = [drawn[k] for k in IMPERFECTION_KEYS]
        if self.features is not None:
            assert setup.c_goal is not None
            self.features.start(i, setup.c_goal, setup.goal_points)

    def imperfections_info(self, rows: Any) -> dict[str, NDArray[np.float64]]:
        """Return the drawn imperfections of the envs ``rows``: ``{key: (k,) array}``."""
        table = self.imperfections[rows]
        return {k: table[:, j] for j, k in enumerate(IMPERFECTION_KEYS)}
