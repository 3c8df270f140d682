"""A reverse curriculum for training: starts near the goal first, then farther away.

A policy from scratch in random rooms rarely reaches the goal at 2 cm / 2 deg by chance, so it
gets almost no success signal. A reverse curriculum (Florensa et al., 2017, "Reverse
Curriculum Generation for Reinforcement Learning") starts the robot close to the goal, where
success is likely, and widens the start distribution as training goes on. Here the env's
``start_reach`` (:attr:`radial_ibvs_gym.envs.parking.ParkingEnv.start_reach`) grows linearly
from ``start`` to ``1`` over the first ``until`` fraction of the training steps, then stays at
``1`` (the full task). Evaluation envs are left at ``1``: they measure the full task.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from stable_baselines3.common.callbacks import BaseCallback

__all__ = ["CurriculumConfig", "StartReachCurriculum"]


@dataclass(frozen=True)
class CurriculumConfig:
    """A linear reverse curriculum on the env's ``start_reach``.

    Attributes
    ----------
    start
        ``start_reach`` at the first step, in ``(0, 1]``.
    until
        The fraction of the training steps after which ``start_reach`` is 1, in ``(0, 1]``.
    """

    start: float = 0.1
    until: float = 0.5

    @classmethod
    def from_mapping(cls, data: Mapping[str, Any], where: str) -> CurriculumConfig:
        """Validate a ``curriculum:`` config entry (``start``, ``until``)."""
        if not isinstance(data, Mapping):
            raise ValueError(f"{where} must be a mapping (start, until), got {data!r}")
        unknown = sorted(set(data) - {"start", "until"})
        if unknown:
            raise ValueError(f"{where}: unknown key(s) {unknown}; valid: ['start', 'until']")
        values = {}
        for key in ("start", "until"):
            value = data.get(key, getattr(cls, key))
            if (
                isinstance(value, bool)
                or not isinstance(value, int | float)
                or not (math.isfinite(value) and 0 < value <= 1)
            ):
                raise ValueError(f"{where}.{key} must be a number in (0, 1], got {value!r}")
            values[key] = float(value)
        return cls(**values)

    def as_dict(self) -> dict[str, float]:
        """Return the config as a plain dict (for the model's metadata)."""
        return {"start": self.start, "until": self.until}

    def reach(self, progress: float) -> float:
        """``start_reach`` at ``progress`` (the fraction of training done, in ``[0, 1]``)."""
        fraction = min(max(progress / self.until, 0.0), 1.0)
        return self.start + (1.0 - self.start) * fraction


class StartReachCurriculum(BaseCallback):
    """Set the training envs' ``start_reach`` before each rollout (SB3 callback).

    Parameters
    ----------
    config
        The schedule.
    total_timesteps
        The run's total env steps (progress is ``num_timesteps / total_timesteps``).
    """

    def __init__(self, config: CurriculumConfig, total_timesteps: int) -> None:
        super().__init__()
        self.config = config
        self.total_timesteps = int(total_timesteps)
        self.current: float | None = None

    def _on_rollout_start(self) -> None:
        reach = self.config.reach(self.num_timesteps / self.total_timesteps)
        if reach != self.current:
            self.training_env.set_attr("start_reach", reach)
            self.current = reach
        self.logger.record("curriculum/start_reach", reach)

    def _on_step(self) -> bool:
        return True
