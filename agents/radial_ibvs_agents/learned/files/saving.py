"""Save a model trained with stable-baselines3 as a model directory that every command takes.

:func:`save_model_dir` writes the files :func:`radial_ibvs_agents.load` reads (no pickles:
:mod:`radial_ibvs_agents.learned.files.model_files`) and a ``metadata.json`` holding the env id and
the ``gym.make`` arguments the model was trained with. Those are read from the env the model was
trained on (``model.get_env()``, or an env or ``VecEnv`` given), so they are not typed again;
:func:`env_spec_of` is that reading.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from radial_ibvs_agents.io import write_json
from radial_ibvs_agents.learned.files.model_dir import replace_model_files
from radial_ibvs_agents.learned.files.model_files import (
    algorithms,
    save_normalization,
    save_policy,
    space_to_json,
)
from radial_ibvs_agents.learned.files.observation_wrappers import (
    describe_wrappers,
    replay_space,
    same_space,
)
from radial_ibvs_gym.registration import check_env_id

__all__ = ["env_spec_of", "save_model_dir"]

#: ``gym.make``/``gym.make_vec`` arguments that are not the env's own (wrappers, batching)
_NOT_ENV_ARGUMENTS = frozenset(
    {
        "render_mode",
        "max_episode_steps",
        "num_envs",
        "vectorization_mode",
        "vector_kwargs",
        "autoreset_mode",
        "disable_env_checker",
        "wrappers",
    }
)


def _layers(env: Any) -> list[Any]:
    """``env`` and what it wraps: SB3 ``VecEnv`` wrappers, its envs, Gymnasium wrappers."""
    seen: list[Any] = []
    while env is not None and len(seen) < 64:
        seen.append(env)
        if hasattr(env, "venv"):  # VecNormalize, VecMonitor, VecTransposeImage...
            env = env.venv
        elif hasattr(env, "envs") and env.envs:  # DummyVecEnv, SyncVectorEnv
            env = env.envs[0]
        elif hasattr(env, "env") and env.env is not env:  # NativeVecEnv, gymnasium wrappers
            env = env.env
        else:
            break
    return seen


def env_spec_of(env: Any) -> tuple[str, dict[str, Any]]:
    """Return the env id and ``gym.make`` arguments of an env, a vector env or an SB3 ``VecEnv``.

    Parameters
    ----------
    env
        What ``gym.make`` or ``gym.make_vec`` returned, :func:`radial_ibvs_agents.make_vec_env`'s
        ``VecEnv``, SB3's ``make_vec_env``/``DummyVecEnv``/``SubprocVecEnv`` of such envs, or
        any wrapper of these.

    Returns
    -------
    tuple
        The env id (one of this package's) and its arguments, without the ones that belong to
        wrappers or batching (``render_mode``, ``max_episode_steps``, ``num_envs``...).

    Raises
    ------
    ValueError
        If no layer of ``env`` carries a Gymnasium spec, or its id is not this package's.
    """
    spec = None
    for layer in _layers(env):
        spec = getattr(layer, "spec", None)
        if spec is not None:
            break
    if spec is None and hasattr(env, "get_attr"):  # SubprocVecEnv: ask the first worker
        spec = env.get_attr("spec", [0])[0]
    if spec is None:
        raise ValueError(
            f"{type(env).__name__} carries no Gymnasium spec (it was not made by gym.make or "
            "gym.make_vec): give env_id and env_kwargs"
        )
    env_id = check_env_id(spec.id, f"{type(env).__name__}.spec.id")
    kwargs = {k: v for k, v in (spec.kwargs or {}).items() if k not in _NOT_ENV_ARGUMENTS}
    return env_id, kwargs


def _vec_normalize(env: Any) -> Any:
    from stable_baselines3.common.vec_env import VecNormalize

    return next((layer for layer in _layers(env) if isinstance(layer, VecNormalize)), None)


def _observation_path(model: Any, source: Any) -> dict[str, Any]:
    """Return the metadata entries of what stood between the env and the policy.

    ``observation_wrappers`` (:mod:`~radial_ibvs_agents.learned.files.observation_wrappers`)
    and, where they change the observation's shape, ``env_observation_space`` (the env's own,
    one robot's). Nothing when the policy sees the env's observations as they are.

    Raises
    ------
    ValueError
        If the policy's observation space is not what the env's becomes behind the recorded
        wrappers (a wrapper that could not be read: a Gymnasium wrapper inside the envs).
    """
    from stable_baselines3.common.vec_env import VecEnv, VecEnvWrapper

    if isinstance(source, VecEnv):
        wrappers = describe_wrappers(source)
        base = source
        while isinstance(base, VecEnvWrapper):
            base = base.venv
        space = base.observation_space
    elif getattr(source, "observation_space", None) is not None:  # one env, given as env=
        wrappers, space = [], source.observation_space
    else:
        return {}
    wanted = model.policy.observation_space
    if not same_space(replay_space(wrappers, space), wanted):
        # the algorithm transposes channel-last images itself, on an env given as it was
        if same_space(replay_space([*wrappers, {"name": "transpose_image"}], space), wanted):
            wrappers.append({"name": "transpose_image"})
        else:
            raise ValueError(
                f"the model sees {wanted}, but the env gives {space} and its wrappers "
                f"{[w['name'] for w in wrappers]} make it {replay_space(wrappers, space)}: "
                "save the model with the env it was trained on (model.get_env())"
            )
    if not wrappers:
        return {}
    entries: dict[str, Any] = {"observation_wrappers": wrappers}
    if any(w["name"] != "normalize" for w in wrappers):
        entries["env_observation_space"] = space_to_json(space)
    return entries


def save_model_dir(
    model: Any,
    directory: Path | str,
    *,
    env: Any = None,
    env_id: str | None = None,
    env_kwargs: dict[str, Any] | None = None,
    normalization: Any = None,
    metadata: dict[str, Any] | None = None,
) -> Path:
    """Make a model trained with stable-baselines3 loadable by :func:`radial_ibvs_agents.load`.

    Writes ``policy.safetensors``, ``policy.json``, ``metadata.json`` and, when observations were
    normalised, ``normalization.npz``, all at once
    (:func:`~radial_ibvs_agents.learned.files.model_dir.replace_model_files`): into an existing
    folder, the model files of an earlier model are replaced or removed, other files kept. The
    directory is then what ``radial-ibvs evaluate --policy DIR``, ``radial-ibvs benchmark
    --policies DIR`` and ``radial_ibvs_agents.load(DIR)`` take.

    Parameters
    ----------
    model
        A trained ``PPO``, ``A2C``, ``SAC``, ``TD3``, ``TQC`` or ``RecurrentPPO`` model (the
        algorithms of :func:`~radial_ibvs_agents.learned.files.model_files.algorithms`), with
        any policy (``MultiInputPolicy``, ``CnnPolicy``, ``MultiInputLstmPolicy``...), HER's
        buffer or not.
    directory
        The model directory to write (created).
    env
        The env the model was trained on (an env, a vector env or a ``VecEnv``); default:
        ``model.get_env()``. The env id and arguments are read from it
        (:func:`env_spec_of`), and its ``VecNormalize``, if any, gives ``normalization``. Its
        observation wrappers (``VecFrameStack``, ``VecTransposeImage``, ``VecNormalize``) are
        recorded, so that the loaded policy takes the env's own observations
        (:mod:`~radial_ibvs_agents.learned.files.observation_wrappers`).
    env_id, env_kwargs
        The Gymnasium id and ``gym.make`` arguments, where no env carries them (or to
        override what it carries).
    normalization
        The training ``VecNormalize``; default: the one wrapping ``env``, if any.
    metadata
        More entries for ``metadata.json``.

    Returns
    -------
    pathlib.Path
        ``directory``.

    Raises
    ------
    ValueError
        For a model of another algorithm, an env id that is not this package's (or none), or
        an observation wrapper that cannot be replayed (named).

    Examples
    --------
    >>> from stable_baselines3 import PPO
    >>> from radial_ibvs_agents import load, make_vec_env
    >>> venv = make_vec_env("RadialIBVS/Parking-v0", 4, seed=0, physics="kinematic")
    >>> model = PPO("MultiInputPolicy", venv).learn(2048)  # doctest: +SKIP
    >>> save_model_dir(model, "my-model")  # doctest: +SKIP
    >>> load("./my-model")  # doctest: +SKIP
    """
    found = algorithms()
    algo = next((k for k, cls in found.items() if type(model) is cls), None)
    algo = algo or next((k for k, cls in found.items() if isinstance(model, cls)), None)
    if algo is None:
        raise ValueError(f"model must be one of {sorted(algorithms())}, got {type(model).__name__}")
    source = env if env is not None else model.get_env()
    if env_id is None:
        if source is None:
            raise ValueError("the model has no env: give env (or env_id and env_kwargs)")
        env_id, read = env_spec_of(source)
        env_kwargs = {**read, **(env_kwargs or {})}
    check_env_id(env_id, "env_id")
    if normalization is None and source is not None:
        normalization = _vec_normalize(source)
    meta = {
        "algo": algo,
        "env_id": env_id,
        "env_kwargs": dict(env_kwargs or {}),
        **_observation_path(model, source),
        **(metadata or {}),
    }
    with replace_model_files(directory) as staging:  # all at once, no stale file left
        save_policy(model, staging, algo)
        if normalization is not None:
            save_normalization(normalization, staging / "normalization.npz")
        write_json(staging / "metadata.json", meta)
    return Path(directory)
