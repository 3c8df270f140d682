"""stable-baselines3's ``VecEnv`` over the native batched envs: ``make_vec_env``.

SB3 and Gymnasium disagree on vector envs: SB3 resets an env inside ``step_wait`` and puts its
last observation in ``infos[i]["terminal_observation"]``; Gymnasium returns a dict of arrays.
:class:`NativeVecEnv` is the small adapter between the two, over
:class:`~radial_ibvs_gym.envs.parking_vector.ParkingVectorEnv` in its ``same_step``
autoreset mode, so PPO gets ``N`` robots stepped in one batched call instead of ``N`` scalar
envs stepped one after the other (``DummyVecEnv``).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import Any

import gymnasium as gym
import numpy as np
from stable_baselines3.common.vec_env import VecEnv, VecMonitor

import radial_ibvs_gym  # noqa: F401  (registers the environments)
from radial_ibvs_gym.envs.autoreset import AutoresetMode
from radial_ibvs_gym.registration import VECTOR_ENTRY_POINTS

__all__ = ["NativeVecEnv", "make_vec_env", "spaces_env"]


class NativeVecEnv(VecEnv):
    """An SB3 ``VecEnv`` backed by a native batched env (reset inside ``step_wait``).

    Parameters
    ----------
    env
        A :class:`~radial_ibvs_gym.envs.parking_vector.ParkingVectorEnv` made with
        ``autoreset_mode="same_step"``.

    Notes
    -----
    SB3's semantics: ``dones = terminated | truncated``; for an env that ended,
    ``infos[i]["terminal_observation"]`` holds its last observation and
    ``infos[i]["TimeLimit.truncated"]`` whether the time limit (and not the task) ended it;
    the returned observation is already the next episode's first. ``seed(s)`` seeds env ``i``
    with ``s + i`` at the next reset, as SB3's ``make_vec_env`` does.
    """

    def __init__(self, env: Any) -> None:
        if env.metadata.get("autoreset_mode") != AutoresetMode.SAME_STEP:
            raise ValueError("NativeVecEnv needs a vector env with autoreset_mode='same_step'")
        self.env = env
        super().__init__(env.num_envs, env.single_observation_space, env.single_action_space)
        self._actions: np.ndarray | None = None

    def reset(self) -> Any:
        """Reset every env and return the observations.

        The seeds of :meth:`seed` and the options of ``set_options`` apply once.
        """
        seeds = [s if s is None else int(s) for s in self._seeds]
        options = self._options[0] if self._options else {}
        if any(o != options for o in self._options):
            raise ValueError("the native vector env takes one set of reset options for all envs")
        obs, info = self.env.reset(
            seed=seeds if any(s is not None for s in seeds) else None, options=options or None
        )
        self._reset_seeds()
        self._reset_options()
        self.reset_infos = _split(info, self.num_envs)
        return obs

    def step_async(self, actions: np.ndarray) -> None:
        """Store the actions ``(N, 2)`` for :meth:`step_wait`."""
        self._actions = actions

    def step_wait(self) -> tuple[Any, np.ndarray, np.ndarray, list[dict[str, Any]]]:
        """Step every env; the envs that ended are reset (see the class notes)."""
        if self._actions is None:
            raise RuntimeError("call step_async() before step_wait()")
        obs, reward, terminated, truncated, info = self.env.step(self._actions)
        self._actions = None
        dones = terminated | truncated
        infos = _split(info, self.num_envs)
        if dones.any():
            final_obs, final_info = info["final_obs"], info["final_info"]
            finals = _split(final_info, self.num_envs)
            for i in np.flatnonzero(dones).tolist():
                infos[i] = {
                    **finals[i],
                    "terminal_observation": final_obs[i],
                    "TimeLimit.truncated": bool(truncated[i] and not terminated[i]),
                }
        return obs, reward.astype(np.float32), dones, infos

    def close(self) -> None:
        """Close the env."""
        self.env.close()

    def get_attr(self, attr_name: str, indices: Any = None) -> list[Any]:
        """Read an attribute of the batched env, or of its config, once per index.

        The batched env has one configuration for all its envs (``env.config``): an argument
        such as ``obs_mode`` is read there.
        """
        if hasattr(self.env, attr_name):
            value = getattr(self.env, attr_name)
        else:
            value = getattr(self.env.config, attr_name)
        return [value for _ in self._get_indices(indices)]

    def set_attr(self, attr_name: str, value: Any, indices: Any = None) -> None:
        """Set a settable property of the batched env (``start_reach``) for all its envs.

        The batched env has one configuration for all its envs: ``indices`` must name them all.
        """
        prop = getattr(type(self.env), attr_name, None)
        if not (isinstance(prop, property) and prop.fset is not None):
            raise AttributeError(f"cannot set {attr_name!r} on a native vector env")
        if sorted(self._get_indices(indices)) != list(range(self.num_envs)):
            raise AttributeError(f"{attr_name!r} is shared by all envs: set it for all of them")
        setattr(self.env, attr_name, value)

    def env_method(
        self, method_name: str, *method_args: Any, indices: Any = None, **method_kwargs: Any
    ) -> list[Any]:
        """Call a method of the batched env (``compute_reward`` for HER), once per index."""
        if method_name == "compute_reward":
            return [self.env.compute_reward(*method_args, **method_kwargs)]
        method = getattr(self.env, method_name)
        return [method(*method_args, **method_kwargs) for _ in self._get_indices(indices)]

    def env_is_wrapped(self, wrapper_class: type, indices: Any = None) -> list[bool]:
        """Return ``False`` for each env: they carry no Gymnasium wrapper."""
        return [False for _ in self._get_indices(indices)]

    def get_images(self) -> Sequence[np.ndarray | None]:
        """Return ``None`` for each env: the native env does not render."""
        return [None for _ in range(self.num_envs)]


def _split(info: dict[str, Any], n: int) -> list[dict[str, Any]]:
    """Split a Gymnasium dict-of-arrays ``info`` into ``n`` per-env dicts (masked keys out)."""
    out: list[dict[str, Any]] = [{} for _ in range(n)]
    for key, value in info.items():
        if key.startswith("_") or key in ("final_obs", "final_info"):
            continue
        mask = info.get(f"_{key}")
        rows: Iterable[Any] = (
            _split(value, n)
            if isinstance(value, dict)
            else (list(value) if value.ndim > 1 else value.tolist())
        )
        for i, row in enumerate(rows):
            if mask is None or mask[i]:
                out[i][key] = row
    return out


def make_vec_env(
    env_id: str,
    n_envs: int = 1,
    seed: int | None = None,
    *,
    monitor: bool = True,
    **env_kwargs: Any,
) -> VecEnv:
    """Make an SB3 ``VecEnv`` of ``n_envs`` robots backed by the native batched env.

    Parameters
    ----------
    env_id
        ``"RadialIBVS/Parking-v0"`` or ``"RadialIBVS/ParkingGoal-v1"``.
    n_envs
        Number of envs (>= 1).
    seed
        Env ``i`` is seeded ``seed + i`` at the first reset (``None``: random).
    monitor
        Wrap in SB3's ``VecMonitor`` (episode returns and lengths in ``infos[i]["episode"]``,
        as SB3's own ``make_vec_env`` does with ``Monitor``).
    **env_kwargs
        The scalar env's keyword arguments (``scenario``, ``physics``, ``obs_mode``...).

    Returns
    -------
    VecEnv
        Works with every SB3 algorithm and under ``VecNormalize``.

    Raises
    ------
    ValueError
        For an id without a native vector env (use SB3's ``make_vec_env`` for it), or a bad
        keyword argument.
    """
    if env_id not in VECTOR_ENTRY_POINTS:
        raise ValueError(
            f"{env_id!r} has no native vector env; valid: {sorted(VECTOR_ENTRY_POINTS)} "
            "(use stable_baselines3.common.env_util.make_vec_env for the others)"
        )
    env = gym.make_vec(
        env_id,
        num_envs=n_envs,
        vectorization_mode="vector_entry_point",
        autoreset_mode="same_step",
        **env_kwargs,
    )
    venv: VecEnv = NativeVecEnv(env)
    if seed is not None:
        venv.seed(seed)
    return VecMonitor(venv) if monitor else venv


def spaces_env(observation_space: Any, action_space: Any) -> Any:
    """Return a ``VecEnv`` with just the spaces SB3 needs to build a policy (never stepped)."""
    from stable_baselines3.common.vec_env import DummyVecEnv

    class _Spaces(gym.Env):
        def __init__(self) -> None:
            self.observation_space, self.action_space = observation_space, action_space

    return DummyVecEnv([_Spaces])
