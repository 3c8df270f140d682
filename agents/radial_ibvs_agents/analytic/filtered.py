"""A temporal filter on the image points, in front of any image-based policy.

Pixel noise makes the IBVS estimate of the goal direction meaningless near the goal, where the
robot moves slowly: averaging each landmark's image point over the last steps removes most of
it at little lag. The filter is an exponential moving average per landmark, restarted at the
start of an episode and whenever a landmark reappears; the averaged points are put back on the
unit circle. Its memory travels in SB3's ``state`` (as a recurrent policy's does), so the
policy itself stays stateless and one object serves a batch of robots.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

__all__ = ["FilteredPolicy"]


class FilteredPolicy:
    """An image-based policy fed exponentially averaged image points.

    Parameters
    ----------
    base
        The policy to feed (``predict`` reading ``observation["points"]`` and ``["visible"]``).
    smoothing
        Weight of the past in ``x_f <- smoothing x_f + (1 - smoothing) x``, in ``[0, 1)``; 0
        is no filtering. With a 0.1 s step, 0.7 averages over about 0.3 s.
    """

    #: how it runs in a batch of episodes (:mod:`radial_ibvs_agents.rollouts`): one ``predict`` for
    #: every robot, each robot's action as alone
    batch_mode = "batch"

    def __init__(self, base: Any, smoothing: float = 0.7) -> None:
        if not (math.isfinite(smoothing) and 0.0 <= smoothing < 1.0):
            raise ValueError(f"smoothing must be in [0, 1), got {smoothing!r}")
        self.base = base
        self.smoothing = float(smoothing)

    def __repr__(self) -> str:
        return f"FilteredPolicy({self.base!r}, smoothing={self.smoothing})"

    @property
    def env_kwargs(self) -> dict[str, Any]:
        """What the base policy needs from ``gym.make``."""
        return dict(self.base.env_kwargs)

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
            The env's observation, unbatched or batched (``points`` ``(2N,)`` or ``(B, 2N)``).
        state
            The filter's memory returned by the previous call (``None``: start afresh).
        episode_start
            ``(B,)`` (or ``(1,)``) booleans: restart the filter of these robots.
        deterministic
            Passed to the base policy.

        Returns
        -------
        tuple
            ``(action, state)``: the base policy's action on the filtered points, and the
            filter's memory to pass back at the next step.
        """
        points = np.asarray(observation["points"], dtype=np.float64)
        batched = points.ndim == 2
        x = points.reshape(len(points) if batched else 1, -1, 2)
        visible = np.asarray(observation["visible"]).reshape(len(x), -1) > 0.5
        restart = np.zeros(len(x), dtype=bool)
        if episode_start is not None:
            restart |= np.broadcast_to(np.asarray(episode_start, dtype=bool).reshape(-1), len(x))
        if state is None or state[0].shape != x.shape:
            previous, was_visible = x, np.zeros_like(visible)
        else:
            previous, was_visible = state
        keep = (was_visible & visible & ~restart[:, None])[..., None]
        a = self.smoothing
        filtered = np.where(keep, a * previous + (1.0 - a) * x, x)
        norm = np.hypot(filtered[..., 0], filtered[..., 1])[..., None]
        filtered = np.where(norm > 1e-9, filtered / np.where(norm > 1e-9, norm, 1.0), filtered)
        fed = {**observation, "points": filtered.reshape(points.shape).astype(np.float32)}
        action, _ = self.base.predict(fed, None, episode_start, deterministic)
        return action, (filtered, visible)

    @staticmethod
    def select_state(
        state: tuple[np.ndarray, np.ndarray], rows: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """Return the memory of the robots at positions ``rows`` of the batch."""
        return state[0][rows], state[1][rows]
