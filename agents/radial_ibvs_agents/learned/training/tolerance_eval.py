"""Training evaluations at the three tolerances of the benchmark rows (2 cm, 10 cm, 30 cm).

SB3's ``EvalCallback`` records the env's success (2 cm / 2 deg) of each evaluation episode.
A policy that learns slowly is often near the goal long before it is within 2 cm of it, so
:class:`ToleranceEvalCallback` also records, from each episode's last ``info``, whether it
ended within 10 cm / 5 deg and 30 cm / 15 deg (the rule of the benchmark's
``success_by_tolerance``: the env's success, or a final pose that close without a collision),
and writes them after every evaluation to ``<log_path>/tolerances.npz``: ``timesteps`` ``(E,)``
and one ``(E,)`` success rate per tolerance, keyed by name (``"10cm/5deg"``).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from stable_baselines3.common.callbacks import EvalCallback

from radial_ibvs_agents.io import write_atomic
from radial_ibvs_agents.rows import TASK_TOLERANCE, TOLERANCES

__all__ = ["ToleranceEvalCallback", "read_tolerance_curve", "success_within"]


def success_within(info: dict[str, Any], position_m: float, heading_deg: float) -> bool:
    """Whether an episode whose last ``info`` is ``info`` ended within a tolerance.

    The env's success, or a final pose within ``position_m`` metres and ``heading_deg``
    degrees of the goal unless a collision ended the episode (``EpisodeLog.success_at``).
    """
    if bool(info.get("is_success", False)):
        return True
    if bool(info.get("collision", False)) or "position_error_m" not in info:
        return False
    return (
        float(info["position_error_m"]) <= position_m
        and float(info["heading_error_deg"]) <= heading_deg
    )


class ToleranceEvalCallback(EvalCallback):
    """``EvalCallback`` that also records success at each of the reported tolerances.

    The tolerances: :data:`radial_ibvs_agents.rows.TOLERANCES`.

    Takes ``EvalCallback``'s arguments; ``log_path`` is needed (the rates are written there).
    """

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self._within: dict[str, list[bool]] = {name: [] for name in TOLERANCES}
        self.tolerance_rates: dict[str, list[float]] = {name: [] for name in TOLERANCES}
        self.tolerance_timesteps: list[int] = []

    def _log_success_callback(self, locals_: dict[str, Any], globals_: dict[str, Any]) -> None:
        super()._log_success_callback(locals_, globals_)
        if locals_["done"]:
            info = locals_["info"]
            for name, (position_m, heading_deg) in TOLERANCES.items():
                self._within[name].append(success_within(info, position_m, heading_deg))

    def _on_step(self) -> bool:
        evaluating = self.eval_freq > 0 and self.n_calls % self.eval_freq == 0
        if evaluating:
            for episodes in self._within.values():
                episodes.clear()
        result = super()._on_step()
        if evaluating and self._within[TASK_TOLERANCE]:
            self.tolerance_timesteps.append(int(self.num_timesteps))
            for name, episodes in self._within.items():
                self.tolerance_rates[name].append(float(np.mean(episodes)))
            if self.log_path is not None:
                self._write(Path(self.log_path).parent / "tolerances.npz")
        return result

    def _write(self, path: Path) -> None:
        import io

        arrays: dict[str, Any] = {
            name: np.asarray(r, dtype=np.float64) for name, r in self.tolerance_rates.items()
        }
        arrays["timesteps"] = np.asarray(self.tolerance_timesteps, dtype=np.int64)
        buffer = io.BytesIO()
        np.savez(buffer, **arrays)
        write_atomic(path, buffer.getvalue())


def read_tolerance_curve(path: Path | str) -> dict[int, dict[str, float]]:
    """Read ``tolerances.npz``: ``{timesteps: {tolerance name: success rate}}`` (empty if none).

    Only plain arrays are read (``allow_pickle=False``); names other than the known
    tolerances are ignored.
    """
    path = Path(path)
    if not path.is_file():
        return {}
    with np.load(path, allow_pickle=False) as data:
        steps = [int(t) for t in data["timesteps"]]
        rates = {name: data[name] for name in TOLERANCES if name in data.files}
    return {t: {name: float(r[k]) for name, r in rates.items()} for k, t in enumerate(steps)}
