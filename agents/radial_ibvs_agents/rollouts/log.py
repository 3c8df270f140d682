"""One episode's record: its trajectory, observations, last ``info`` and measures.

:class:`EpisodeLog` is what every rollout returns (:mod:`radial_ibvs_agents.rollouts`); its row, the
flat JSON object of the tables, is :func:`radial_ibvs_agents.rows.episode_row`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from radial_ibvs_gym.envs.rules import pose_errors

__all__ = ["EpisodeLog"]


@dataclass
class EpisodeLog:
    """One episode of a policy in a ``Parking-v0``-like env.

    Attributes
    ----------
    policy, scenario, physics
        Names (the policy's as given to :func:`run_episode`).
    task, seed
        The episode's task index and reset seed.
    control_dt
        Control period, seconds.
    poses
        ``(T + 1, 3)`` robot poses ``(x, y, yaw)`` from the reset on, metres and radians.
    actions
        ``(T, 2)`` actions in ``[-1, 1]``.
    points, visible
        ``(T + 1, N, 2)`` observed image points ``x_n`` (zeros where hidden) and ``(T + 1, N)``
        visibility.
    goal_points
        ``(N, 2)`` the goal image ``x_n*``.
    info
        The last ``info``.
    compute_s
        Seconds spent in ``predict`` over the episode (stepped in a batch: the robot's share).
    batch
        Robots whose actions one ``predict`` gave together at the episode's start (1: alone).
    frames
        ``(T + 1)`` rendered ``(H, W, 3)`` uint8 frames, when :func:`run_episode` was asked to
        record them; empty otherwise.
    extra
        Anything a caller adds (e.g. the suite).
    terminated
        Whether the env terminated the episode (success, collision or lost landmarks) rather
        than truncated it (time limit) or ``max_steps`` stopped it.
    success_hold_steps
        How the env judged success: steps in a row within the tolerances (1: the first step
        within them).
    """

    policy: str
    scenario: str
    physics: str
    task: int | None
    seed: int
    control_dt: float
    poses: NDArray[np.float64]
    actions: NDArray[np.float64]
    points: NDArray[np.float64]
    visible: NDArray[np.bool_]
    goal_points: NDArray[np.float64]
    info: dict[str, Any]
    compute_s: float
    extra: dict[str, Any] = field(default_factory=dict)
    batch: int = 1
    terminated: bool = False
    success_hold_steps: int = 1
    frames: list[NDArray[np.uint8]] = field(default_factory=list, repr=False)

    @property
    def steps(self) -> int:
        """Number of steps taken."""
        return len(self.actions)

    @property
    def times(self) -> NDArray[np.float64]:
        """``(T + 1,)`` time of each pose, seconds."""
        return np.asarray(self.control_dt * np.arange(self.steps + 1), dtype=np.float64)

    @property
    def path_length_m(self) -> float:
        """Length of the driven path, metres."""
        return float(np.linalg.norm(np.diff(self.poses[:, :2], axis=0), axis=1).sum())

    @property
    def control_effort(self) -> float:
        """Mean squared action (actions are fractions of the speed limits), 0 to 2."""
        if self.steps == 0:
            return 0.0
        return float(np.mean(np.sum(self.actions**2, axis=1)))

    @property
    def smoothness(self) -> float:
        """Mean change of the action from one step to the next (0: perfectly smooth)."""
        if self.steps < 2:
            return 0.0
        return float(np.mean(np.linalg.norm(np.diff(self.actions, axis=0), axis=1)))

    @property
    def success(self) -> bool:
        """Whether the env reported success at the end."""
        return bool(self.info.get("is_success", False))

    @property
    def end(self) -> str:
        """Why the episode ended: ``success``, ``collision``, ``lost`` or ``time-out``."""
        if self.success:
            return "success"
        if self.info.get("collision", False):
            return "collision"
        return "lost" if self.terminated else "time-out"

    def success_at(self, position_m: float, heading_deg: float) -> bool:
        """Success at a looser tolerance (metres, degrees), judged by the env's rule.

        With a hold (``success_hold_steps`` > 1, a park): the env's success, or the pose within
        the tolerance for that many steps in a row at some step (the env, judging by that
        tolerance, would have ended the episode there as a success). With 1, the older rule:
        the env's success, or a final pose that close (an episode ended by a collision counts
        only if the env reported success).
        """
        if self.success:
            return True
        if self.success_hold_steps > 1:
            return self.longest_run_within(position_m, heading_deg) >= self.success_hold_steps
        return (
            not self.info.get("collision", False)
            and float(self.info["position_error_m"]) <= position_m
            and float(self.info["heading_error_deg"]) <= heading_deg
        )

    def longest_run_within(self, position_m: float, heading_deg: float) -> int:
        """Return the most steps in a row whose pose lies within a tolerance of the goal.

        The poses after each step are judged as the env judges them (:func:`pose_errors`,
        the heading in radians); 0 when no step comes that close.
        """
        if self.steps == 0:
            return 0
        goal: Any = np.asarray(self.info["goal_pose"], dtype=np.float64)[:, None]
        position, heading = pose_errors(self.poses[1:].T, goal)
        within = (position <= position_m) & (heading <= math.radians(heading_deg))
        longest = run = 0
        for inside in within.tolist():
            run = run + 1 if inside else 0
            longest = max(longest, run)
        return longest
