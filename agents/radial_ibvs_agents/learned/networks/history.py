"""A short history of observations for a learned policy: what a filter needs.

A policy that sees only the current image cannot average out pixel noise or bridge a landmark
missed for a few steps. :class:`HistoryStack` adds the previous ``frames - 1`` values of some
observation keys, as keys ``KEY@-1``, ``KEY@-2``, ... (``@-1`` the step before). At an
episode's first step the history is filled with that first observation.

The same stack serves training (a batch of robots, reset where ``dones``) and deployment
(:class:`HistoryPolicy`, which keeps the stack in the ``state`` of SB3's ``predict``), so a
model sees the same inputs in both.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from gymnasium import spaces

from radial_ibvs_gym.limits import MAX_HISTORY_FRAMES

__all__ = [
    "HistoryConfig",
    "HistoryPolicy",
    "HistoryStack",
    "history_key",
    "history_space",
    "history_vec_env",
]

#: the keys stacked by default: what changes from step to step in the features observation
DEFAULT_KEYS = ("points", "visible", "c_error", "alpha_m_error")


@dataclass(frozen=True)
class HistoryConfig:
    """How many frames of which keys a policy sees.

    Attributes
    ----------
    frames
        Frames seen, the current one included (>= 2).
    keys
        The observation keys stacked (those that change along an episode).
    """

    frames: int = 4
    keys: tuple[str, ...] = DEFAULT_KEYS

    @classmethod
    def from_mapping(cls, data: Any, where: str) -> HistoryConfig:
        """Validate a ``history:`` entry (``frames``, ``keys``); errors name the value."""
        if not isinstance(data, Mapping):
            raise ValueError(f"{where} must be a mapping with 'frames' and 'keys', got {data!r}")
        unknown = sorted(set(data) - {"frames", "keys"})
        if unknown:
            raise ValueError(f"{where}: unknown key(s) {unknown}; valid: ['frames', 'keys']")
        frames = data.get("frames", cls.frames)
        if (
            isinstance(frames, bool)
            or not isinstance(frames, int)
            or not 2 <= frames <= MAX_HISTORY_FRAMES
        ):
            raise ValueError(
                f"{where}.frames must be an integer in [2, {MAX_HISTORY_FRAMES}] "
                f"(MAX_HISTORY_FRAMES), got {frames!r}"
            )
        keys = data.get("keys", list(cls.keys))
        names_ok = isinstance(keys, list | tuple) and all(isinstance(k, str) for k in keys)
        if not names_ok or not keys:
            raise ValueError(f"{where}.keys must be a non-empty list of key names, got {keys!r}")
        return cls(frames, tuple(keys))

    def as_dict(self) -> dict[str, Any]:
        """Return the entry as written in a config or a model's metadata."""
        return {"frames": self.frames, "keys": list(self.keys)}


def history_key(key: str, lag: int) -> str:
    """Return the name of ``key`` ``lag`` steps ago (``points@-1``)."""
    return f"{key}@-{lag}"


def history_space(config: HistoryConfig | None, observation_space: Any) -> spaces.Dict:
    """Return the ``Dict`` space of the stacked observations of ``observation_space``.

    Raises
    ------
    ValueError
        If a stacked key is not in the observation (naming it).
    """
    base = dict(observation_space.spaces)
    if config is None:
        return spaces.Dict(base)
    missing = sorted(set(config.keys) - set(base))
    if missing:
        raise ValueError(f"history keys {missing} are not in the observation {sorted(base)}")
    extra = {history_key(k, lag): base[k] for k in config.keys for lag in range(1, config.frames)}
    return spaces.Dict({**base, **extra})


class HistoryStack:
    """The stacked observations of a batch of robots.

    Parameters
    ----------
    config
        Frames and keys; ``None`` passes the observations through unchanged.
    n
        Robots in the batch.
    """

    def __init__(self, config: HistoryConfig | None, n: int) -> None:
        self.config, self.n = config, n
        self._past: dict[str, np.ndarray] = {}

    def reset(self, obs: Mapping[str, np.ndarray]) -> dict[str, np.ndarray]:
        """Start every robot's history at ``obs`` (batched, ``(n, ...)`` per key)."""
        return self.step(obs, np.ones(self.n, dtype=bool))

    def step(self, obs: Mapping[str, np.ndarray], starts: np.ndarray) -> dict[str, np.ndarray]:
        """Push ``obs`` (batched); robots with ``starts`` begin a new history there."""
        out = {k: np.asarray(v) for k, v in obs.items()}
        if self.config is None:
            return out
        starts = np.asarray(starts, dtype=bool).reshape(-1)
        for key in self.config.keys:
            now = out[key]
            past = self._past.get(key)
            if past is None or past.shape[1:] != now.shape:
                past = np.repeat(now[None], self.config.frames - 1, axis=0)
                starts = np.ones(len(now), dtype=bool)
            past = np.where(starts.reshape(1, -1, *([1] * (now.ndim - 1))), now[None], past)
            for lag in range(1, self.config.frames):
                out[history_key(key, lag)] = past[lag - 1]
            self._past[key] = np.concatenate([now[None], past[:-1]])  # shift: now becomes @-1
        return out

    def peek(self, obs: Mapping[str, np.ndarray], i: int) -> dict[str, np.ndarray]:
        """Return robot ``i``'s stacked observation for ``obs`` (its row) without pushing it.

        For the last observation of an episode (SB3's ``terminal_observation``): the frames
        before it are that episode's.
        """
        out = {k: np.asarray(v) for k, v in obs.items()}
        if self.config is None:
            return out
        for key in self.config.keys:
            past = self._past.get(key)
            for lag in range(1, self.config.frames):
                out[history_key(key, lag)] = out[key] if past is None else past[lag - 1][i : i + 1]
        return out

    def state(self) -> dict[str, np.ndarray]:
        """Return the history kept (for :class:`HistoryPolicy`'s ``state``)."""
        return {k: v.copy() for k, v in self._past.items()}

    def restore(self, state: dict[str, np.ndarray] | None) -> None:
        """Set the history kept (``None``: none, the next step starts one)."""
        self._past = {} if state is None else {k: v.copy() for k, v in state.items()}


class HistoryPolicy:
    """A model trained with a history, behind the common ``predict`` (state: the history).

    Parameters
    ----------
    learned
        The trained model (:class:`radial_ibvs_agents.learned.LearnedPolicy`).
    config
        The history it was trained with.
    """

    #: how it runs in a batch of episodes (:mod:`radial_ibvs_agents.rollouts`): one ``predict`` for
    #: every robot (each robot's action as alone, to the last bits of a batched matrix product)
    batch_mode = "batch"

    def __init__(self, learned: Any, config: HistoryConfig) -> None:
        self.learned, self.config = learned, config
        self.name, self.metadata = learned.name, learned.metadata

    def __repr__(self) -> str:
        return f"HistoryPolicy({self.name!r}, frames={self.config.frames})"

    @property
    def env_kwargs(self) -> dict[str, Any]:
        """The ``gym.make`` arguments the model was trained with."""
        return self.learned.env_kwargs

    @property
    def env_id(self) -> str:
        """The Gymnasium id the model was trained on."""
        return str(self.learned.env_id)

    def check_observation_space(self, space: Any) -> None:
        """Raise a ``ValueError`` if the env's observation is not the model's (less history)."""
        self.learned.check_observation_space(history_space(self.config, space))

    def predict(
        self,
        observation: dict[str, np.ndarray],
        state: Any = None,
        episode_start: np.ndarray | None = None,
        deterministic: bool = True,
    ) -> tuple[np.ndarray, Any]:
        """Action(s) for one observation or a batch; ``state`` carries the history."""
        single = np.asarray(observation["points"]).ndim == 1
        batch = {k: np.asarray(v) for k, v in observation.items()}
        if single:
            batch = {k: v[None] for k, v in batch.items()}
        n = len(batch["points"])
        missing = sorted(set(self.config.keys) - set(batch))
        if missing:
            raise KeyError(f"{self.name} needs observation keys {missing} for its history")
        stack = HistoryStack(self.config, n)
        stack.restore(state)
        starts = np.zeros(n, dtype=bool) if episode_start is None else episode_start
        stacked = stack.step(batch, np.broadcast_to(np.asarray(starts, dtype=bool).reshape(-1), n))
        action, _ = self.learned.predict(stacked, None, None, deterministic)
        action = np.asarray(action, dtype=np.float32)
        return (action[0] if single else action), stack.state()

    @staticmethod
    def select_state(state: dict[str, np.ndarray], rows: np.ndarray) -> dict[str, np.ndarray]:
        """Return the history of the robots at positions ``rows`` of the batch."""
        return {key: past[:, rows] for key, past in state.items()}


def history_vec_env(venv: Any, config: HistoryConfig) -> Any:
    """Wrap an SB3 ``VecEnv`` so that its observations carry the history (training side).

    The stacked keys are those :class:`HistoryPolicy` builds at deployment; each
    ``terminal_observation`` is stacked with its own episode's frames.
    """
    from stable_baselines3.common.vec_env import VecEnvWrapper

    class HistoryVecEnv(VecEnvWrapper):
        def __init__(self) -> None:
            super().__init__(venv, observation_space=history_space(config, venv.observation_space))
            self.stack = HistoryStack(config, venv.num_envs)

        def reset(self) -> Any:
            first: Any = self.venv.reset()
            return self.stack.reset(first)

        def step_wait(self) -> Any:
            obs: Any
            obs, rewards, dones, infos = self.venv.step_wait()
            for i, info in enumerate(infos):
                if "terminal_observation" in info:
                    final = {
                        k: np.asarray(v)[None] for k, v in info["terminal_observation"].items()
                    }
                    stacked = self.stack.peek(final, i)
                    info["terminal_observation"] = {k: v[0] for k, v in stacked.items()}
            return self.stack.step(obs, dones), rewards, dones, infos

    return HistoryVecEnv()
