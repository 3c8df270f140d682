"""Missed detections: landmarks that drop out of the image for a few steps (domain randomisation).

A real detector loses a beacon now and then (glare, occlusion, a blob under threshold) and
finds it again a few frames later. With ``missed_detections={"rate": p, "steps": [lo, hi]}``
each landmark in view is missed with probability ``p`` at each step, and stays hidden (point
zero, ``visible`` 0, its ``c_ij`` pairs out of the features) for a number of steps drawn
uniformly in ``[lo, hi]``. A missed landmark counts as not visible everywhere, the episode's
"lost" rule included. The draws come from a generator of the episode's own, seeded from the
env's at reset, so the same seed gives the same misses, in the scalar and the vector envs.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = ["MissedDetections", "MissedState"]


@dataclass(frozen=True)
class MissedDetections:
    """How often landmarks are missed, and for how long.

    Attributes
    ----------
    rate
        Probability per landmark in view and per step that it is missed, in ``[0, 1)``.
    steps
        ``(lo, hi)``: a miss lasts a number of control steps drawn uniformly in it (>= 1).
    """

    rate: float
    steps: tuple[int, int] = (1, 5)

    @classmethod
    def from_value(cls, value: Any) -> MissedDetections | None:
        """Validate the env argument (``None``, a mapping, or an instance); errors name it."""
        if value is None or isinstance(value, MissedDetections):
            return value
        if not isinstance(value, Mapping):
            raise ValueError(
                f"missed_detections must be a mapping {{'rate': p, 'steps': [lo, hi]}} or None, "
                f"got {value!r}"
            )
        unknown = sorted(set(value) - {"rate", "steps"})
        if unknown:
            raise ValueError(
                f"missed_detections: unknown key(s) {unknown}; valid: ['rate', 'steps']"
            )
        rate = value.get("rate")
        if isinstance(rate, bool) or not isinstance(rate, int | float):
            raise ValueError(f"missed_detections.rate must be a number in [0, 1), got {rate!r}")
        if not (math.isfinite(rate) and 0.0 <= rate < 1.0):
            raise ValueError(f"missed_detections.rate must be a number in [0, 1), got {rate!r}")
        steps = value.get("steps", [1, 5])
        ok = (
            isinstance(steps, list | tuple)
            and len(steps) == 2
            and all(isinstance(s, int) and not isinstance(s, bool) for s in steps)
            and 1 <= steps[0] <= steps[1]
        )
        if not ok:
            raise ValueError(
                f"missed_detections.steps must be integers [lo, hi], 1 <= lo <= hi: {steps!r}"
            )
        return cls(float(rate), (int(steps[0]), int(steps[1])))

    def start(self, rng: np.random.Generator, n: int) -> MissedState:
        """Start an episode's misses for ``n`` landmarks (one draw from the env's ``rng``)."""
        return MissedState(self, np.random.default_rng(int(rng.integers(2**63))), np.zeros(n, int))


@dataclass
class MissedState:
    """An episode's misses: the generator and the steps each landmark stays hidden."""

    config: MissedDetections
    rng: np.random.Generator
    remaining: np.ndarray

    def apply(self, points: np.ndarray, visible: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Hide the missed landmarks of one step: ``points`` ``(N, 2)``, ``visible`` ``(N,)``."""
        visible = np.asarray(visible, dtype=bool)
        fresh = (self.rng.random(len(visible)) < self.config.rate) & visible & (self.remaining == 0)
        lo, hi = self.config.steps
        self.remaining[fresh] = self.rng.integers(lo, hi + 1, int(fresh.sum()))
        hidden = self.remaining > 0
        self.remaining[hidden] -= 1
        if not hidden.any():
            return points, visible
        points = np.where(hidden[:, None], 0.0, points)
        return points, visible & ~hidden
