"""Residual policies: a learned, bounded correction on top of an analytic policy.

The env receives ``clip(base + w * a, -1, 1)`` (``w = scale``, faded near the goal by an
optional ``gate``: :meth:`ResidualConfig.combine`), where ``base`` is the analytic policy's
action (the paper's IBVS by default) and ``a`` in ``[-1, 1]^2`` is the learned policy's. The
learned policy sees the env's observation plus ``base_action``. A freshly initialised SB3
policy has a mean action of about zero (its last layer is initialised with a gain of 0.01), so
training starts at the analytic policy's success rate, and the correction it learns is at most
``scale`` in each action component.

:class:`ResidualVecEnv` is the training side (an SB3 ``VecEnvWrapper``); :class:`ResidualPolicy` the
deployment side, which :func:`radial_ibvs_agents.learned.load` builds when a model's metadata has a
``residual`` entry.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from gymnasium import spaces
from stable_baselines3.common.vec_env import VecEnv, VecEnvWrapper

from radial_ibvs_agents.analytic import ANALYTIC_POLICIES, make_analytic

__all__ = ["BASE_KEY", "ResidualConfig", "ResidualPolicy", "ResidualVecEnv"]

#: the observation key holding the base policy's action
BASE_KEY = "base_action"


@dataclass(frozen=True)
class ResidualConfig:
    """What a residual model is a correction of.

    Attributes
    ----------
    base
        The base policy's name (:data:`radial_ibvs_agents.analytic.ANALYTIC_POLICIES`, e.g.
        ``ibvs-backward``).
    scale
        The largest correction per action component (actions are in ``[-1, 1]``), in ``(0, 2]``.
    gate
        Fade the correction out where the base action is small: it is multiplied by
        ``min(1, |base| / gate)`` (``|base|`` the Euclidean norm of the base action), so that
        near the goal, where the analytic policy slows down and stops, the robot moves as it
        would without correction. ``None``: no fading.
    """

    base: str = "ibvs-backward"
    scale: float = 0.5
    gate: float | None = None

    @classmethod
    def from_mapping(cls, data: Mapping[str, Any], where: str) -> ResidualConfig:
        """Validate a ``residual:`` config entry (``base``, ``scale``); errors name the value."""
        unknown = sorted(set(data) - {"base", "scale", "gate"})
        if unknown:
            raise ValueError(f"{where}: unknown key(s) {unknown}; valid: ['base', 'gate', 'scale']")
        base = str(data.get("base", cls.base))
        if base not in ANALYTIC_POLICIES:
            valid = list(ANALYTIC_POLICIES)
            raise ValueError(f"{where}.base: unknown policy {base!r}; valid: {valid}")
        scale = data.get("scale", cls.scale)
        if not isinstance(scale, int | float) or not (math.isfinite(scale) and 0 < scale <= 2):
            raise ValueError(f"{where}.scale must be a number in (0, 2], got {scale!r}")
        gate = data.get("gate")
        if gate is not None and not (
            isinstance(gate, int | float) and math.isfinite(gate) and gate > 0
        ):
            raise ValueError(f"{where}.gate must be a positive number or null, got {gate!r}")
        return cls(base, float(scale), None if gate is None else float(gate))

    def as_dict(self) -> dict[str, Any]:
        """Return the entry as written in a config or the model's metadata."""
        out: dict[str, Any] = {"base": self.base, "scale": self.scale}
        if self.gate is not None:
            out["gate"] = self.gate
        return out

    def combine(self, base: np.ndarray, correction: np.ndarray) -> np.ndarray:
        """Return the env's action ``clip(base + w * correction, -1, 1)`` (``(2,)`` or ``(B, 2)``).

        ``w = scale``, times ``min(1, |base| / gate)`` with a ``gate``.
        """
        weight = np.full(np.shape(base)[:-1], self.scale, dtype=np.float32)
        if self.gate is not None:
            weight = weight * np.minimum(1.0, np.linalg.norm(base, axis=-1) / self.gate)
        mixed = base + weight[..., None] * np.asarray(correction, dtype=np.float32)
        return np.clip(mixed, -1.0, 1.0).astype(np.float32)

    def make_base(self) -> Any:
        """Build the base policy."""
        return make_analytic(self.base)


class ResidualVecEnv(VecEnvWrapper):
    """Train a correction to a base policy: the env steps ``ResidualConfig.combine(base, a)``.

    Parameters
    ----------
    venv
        The env (a ``Dict`` observation with what the base policy needs).
    residual
        The base policy and the scale.

    Notes
    -----
    The observation gains ``base_action`` ``(2,)``, the base policy's action for it (also in
    each ``terminal_observation``, for SB3's bootstrapping at time limits).
    """

    def __init__(self, venv: VecEnv, residual: ResidualConfig) -> None:
        space = venv.observation_space
        if not isinstance(space, spaces.Dict):
            raise ValueError(f"a residual policy needs a Dict observation, got {space}")
        observation_space = spaces.Dict(
            {**space.spaces, BASE_KEY: spaces.Box(-1.0, 1.0, (2,), np.float32)}
        )
        super().__init__(venv, observation_space=observation_space)
        self.residual = residual
        self.base = residual.make_base()
        self._base_actions = np.zeros((self.num_envs, 2), dtype=np.float32)

    def _with_base(self, obs: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        self._base_actions = np.asarray(self.base.predict(obs)[0], dtype=np.float32)
        return {**obs, BASE_KEY: self._base_actions}

    def reset(self) -> dict[str, np.ndarray]:
        """Reset the envs; the observations carry the base actions."""
        return self._with_base(self.venv.reset())  # type: ignore[arg-type]

    def step_async(self, actions: np.ndarray) -> None:
        """Step with ``clip(base + w * actions, -1, 1)`` (:meth:`ResidualConfig.combine`)."""
        self.venv.step_async(self.residual.combine(self._base_actions, actions))

    def step_wait(self) -> Any:
        """Step the envs; observations (and terminal ones) carry the base actions."""
        obs, rewards, dones, infos = self.venv.step_wait()
        ended = [i for i, info in enumerate(infos) if "terminal_observation" in info]
        if ended:  # the base actions of all the last observations, in one batched call
            finals = [infos[i]["terminal_observation"] for i in ended]
            batch = {k: np.stack([f[k] for f in finals]) for k in finals[0]}
            actions = np.asarray(self.base.predict(batch)[0], dtype=np.float32)
            for i, final, action in zip(ended, finals, actions, strict=True):
                infos[i]["terminal_observation"] = {**final, BASE_KEY: action}
        return self._with_base(obs), rewards, dones, infos  # type: ignore[arg-type]


class ResidualPolicy:
    """A trained correction and its base policy, behind the common ``predict``.

    Parameters
    ----------
    learned
        The trained model (:class:`radial_ibvs_agents.learned.LearnedPolicy`), whose observation has
        ``base_action``.
    residual
        The base policy and the scale it was trained with.
    """

    #: how it runs in a batch of episodes (:mod:`radial_ibvs_agents.rollouts`): one ``predict`` for
    #: every robot (each robot's action as alone, to the last bits of a batched matrix product)
    batch_mode = "batch"

    def __init__(self, learned: Any, residual: ResidualConfig) -> None:
        self.learned = learned
        self.residual = residual
        self.base = residual.make_base()
        self.name = learned.name
        self.metadata = learned.metadata

    def __repr__(self) -> str:
        return (
            f"ResidualPolicy({self.name!r}, base={self.residual.base!r}, "
            f"scale={self.residual.scale})"
        )

    @property
    def env_kwargs(self) -> dict[str, Any]:
        """The ``gym.make`` arguments the model was trained with."""
        return {**self.base.env_kwargs, **self.learned.env_kwargs}

    @property
    def select_state(self) -> Any:
        """The model's ``select_state`` (None: its state cannot be cut to fewer robots)."""
        return getattr(self.learned, "select_state", None)

    def check_observation_space(self, space: Any) -> None:
        """Raise a ``ValueError`` if the env's observation is not the model's (less the base)."""
        full = spaces.Dict(
            {**space.spaces, BASE_KEY: spaces.Box(-1.0, 1.0, (2,), np.float32)}
        ) if isinstance(space, spaces.Dict) else space  # fmt: skip
        self.learned.check_observation_space(full)

    def predict(
        self,
        observation: dict[str, np.ndarray],
        state: Any = None,
        episode_start: np.ndarray | None = None,
        deterministic: bool = True,
    ) -> tuple[np.ndarray, Any]:
        """``clip(base + w * correction, -1, 1)`` for one observation or a batch (``combine``)."""
        base = np.asarray(self.base.predict(observation)[0], dtype=np.float32)
        correction, state = self.learned.predict(
            {**observation, BASE_KEY: base}, state, episode_start, deterministic
        )
        return self.residual.combine(base, correction), state
