"""Trained models as policies: load a saved (or shipped) model with its observation statistics.

A model directory holds ``policy.safetensors`` and ``policy.json`` (the policy's weights and
its description, :mod:`radial_ibvs_agents.learned.files.model_files`), ``normalization.npz`` (the
``VecNormalize`` observation statistics, if training normalised observations) and
``metadata.json`` (algorithm, env id and ``gym.make`` arguments, seed, command, git revision,
training figures); none of them can run code when read. A stable-baselines3 ``model.zip`` may
lie beside them, for SB3 users and for resuming training; loading never reads it. :func:`load`
returns a :class:`LearnedPolicy` with the same ``predict`` as every other policy here,
normalising observations exactly as training did.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from radial_ibvs_agents.learned.files.model_files import (
    DESCRIPTION,
    WEIGHTS,
    has_policy_files,
    load_policy,
    read_normalization,
)
from radial_ibvs_agents.learned.files.observation_wrappers import (
    predict_replayed,
    read_observation_path,
    replay_space,
    same_space,
)
from radial_ibvs_agents.learned.files.sb3_zip import PickleLoadWarning, algo_of_zip, load_sb3_zip
from radial_ibvs_agents.learned.files.threads import threads_for
from radial_ibvs_agents.untrusted import read_json
from radial_ibvs_gym.registration import check_env_id

__all__ = ["MODELS_DIR", "LearnedPolicy", "PickleLoadWarning", "load", "shipped_models"]

#: where the shipped models live (inside the package, so wheels carry them)
MODELS_DIR = Path(__file__).resolve().parents[1] / "models"


class LearnedPolicy:
    """A trained stable-baselines3 model behind the common ``predict`` interface.

    Parameters
    ----------
    model
        The SB3 policy (``stable_baselines3.common.policies.BasePolicy``, a torch module with
        ``predict``), rebuilt from ``policy.safetensors``; with ``trust_pickle``, the SB3
        algorithm loaded from ``model.zip``. Both have ``predict`` and ``observation_space``.
    metadata
        The model's ``metadata.json`` (``env_kwargs`` in particular).
    normalization
        Observation statistics: ``{key: (mean, var)}``, plus ``clip_obs`` and ``epsilon``;
        ``None`` when training did not normalise observations.
    name
        The name it was loaded by.
    """

    #: how it runs in a batch of episodes (:mod:`radial_ibvs_agents.rollouts`): one ``predict`` for
    #: every robot (each robot's action as alone, to the last bits of a batched matrix product)
    batch_mode = "batch"

    def __init__(
        self,
        model: Any,
        metadata: dict[str, Any],
        normalization: dict[str, Any] | None,
        name: str,
    ) -> None:
        self.model = model
        self.metadata = metadata
        self.normalization = normalization
        self.name = name
        #: the observation wrappers replayed before the policy (frame stack, transposition),
        #: and the env's observation space they start from; ``([], None)`` for none
        self.wrappers, self.env_space = read_observation_path(metadata, name)

    def __repr__(self) -> str:
        return f"LearnedPolicy({self.name!r}, algo={self.metadata.get('algo')!r})"

    @property
    def env_id(self) -> str:
        """The Gymnasium id the model was trained on (``RadialIBVS/Parking-v0`` by default)."""
        return str(self.metadata.get("env_id", "RadialIBVS/Parking-v0"))

    @property
    def env_kwargs(self) -> dict[str, Any]:
        """The ``gym.make`` arguments the model was trained with (observation layout)."""
        return dict(self.metadata.get("env_kwargs", {}))

    def check_observation_space(self, space: Any) -> None:
        """Raise a ``ValueError`` naming the difference if ``space`` is not the model's.

        A model trained behind SB3's observation wrappers (a frame stack, channels-first
        images) is compared on what those wrappers make of ``space``.
        """
        if self.env_space is not None:
            try:
                seen = replay_space(self.wrappers, space)
            except (KeyError, ValueError, TypeError, AssertionError) as error:  # SB3's checks
                seen = f"nothing ({type(error).__name__}: {error})"
            if isinstance(seen, str) or not same_space(seen, self.model.observation_space):
                raise ValueError(
                    f"{self.name}: the env's observation {space} becomes {seen} behind the "
                    f"model's wrappers {[w['name'] for w in self.wrappers]}, not the model's "
                    f"{self.model.observation_space} (trained on {self.env_kwargs})"
                )
            return
        mine = self.model.observation_space
        if getattr(mine, "spaces", None) is not None and getattr(space, "spaces", None) is not None:
            missing = sorted(set(mine.spaces) - set(space.spaces))
            if missing:
                raise ValueError(
                    f"{self.name}: the env's observation lacks {missing}; the model was trained "
                    f"with gym.make(..., {self.env_kwargs})"
                )
            for key, sub in mine.spaces.items():
                if sub.shape != space.spaces[key].shape:
                    raise ValueError(
                        f"{self.name}: observation[{key!r}] has shape {space.spaces[key].shape}, "
                        f"the model expects {sub.shape} (trained on {self.env_kwargs})"
                    )
        elif mine.shape != getattr(space, "shape", None):
            raise ValueError(f"{self.name}: observation space {space} is not the model's {mine}")

    def _normalise(self, observation: Any) -> Any:
        """Normalise as the training ``VecNormalize`` did (a Dict by key, a Box as ``obs``)."""
        if self.normalization is None:
            return observation
        clip, eps = self.normalization["clip_obs"], self.normalization["epsilon"]
        stats = self.normalization["stats"]

        def normal(value: Any, key: str) -> np.ndarray:
            value = np.asarray(value, dtype=np.float32)
            if key in stats:
                mean, var = stats[key]
                value = np.clip((value - mean) / np.sqrt(var + eps), -clip, clip)
            return value.astype(np.float32)

        if not isinstance(observation, dict):
            return normal(observation, "obs")
        return {key: normal(observation[key], key) for key in self.model.observation_space.spaces}

    def predict(
        self,
        observation: dict[str, np.ndarray],
        state: Any = None,
        episode_start: np.ndarray | None = None,
        deterministic: bool = True,
    ) -> tuple[np.ndarray, Any]:
        """Action(s) for one observation or a batch, as stable-baselines3's ``predict``.

        A batch of fewer than :data:`~radial_ibvs_agents.learned.files.threads.SMALL_BATCH`
        observations runs on one torch thread, and the caller's thread count is restored after
        the call (:mod:`radial_ibvs_agents.learned.files.threads` says why, and that it is not
        thread-safe).

        Raises
        ------
        KeyError
            If the observation lacks a key the model was trained on (the message names the
            ``gym.make`` arguments to use).
        """
        space = self.model.observation_space if self.env_space is None else self.env_space
        keys = getattr(space, "spaces", None)
        missing = sorted(set(keys) - set(observation)) if isinstance(keys, dict) else []
        if missing:
            raise KeyError(
                f"{self.name} needs observation keys {missing}: make the env with {self.env_kwargs}"
            )
        if self.env_space is not None:  # a frame stack or channels-first images: replayed
            with threads_for(_rows(observation, self.env_space)):
                return predict_replayed(self, observation, state, episode_start, deterministic)
        normalised = self._normalise(observation)
        with threads_for(_rows(normalised, self.model.observation_space)):
            if deterministic and state is None:
                action = self._mean_action(normalised)
                if action is not None:
                    return action, None
            action, state = self.model.predict(normalised, state, episode_start, deterministic)
        return np.asarray(action, dtype=np.float32), state

    def _mean_action(self, observation: dict[str, np.ndarray]) -> np.ndarray | None:
        """Return SB3's deterministic action, computed without SB3's per-call work.

        :func:`~radial_ibvs_agents.learned.files.mean_action.mean_action`.

        ``None`` where the model is not a policy that path fits (it then goes through SB3's
        ``predict``).
        """
        from radial_ibvs_agents.learned.files.mean_action import mean_action

        fast = self._fast_path()
        return None if fast is None else mean_action(*fast, observation)

    def _fast_path(self) -> tuple[Any, list[Any]] | None:
        """Return the SB3 policy and its actor's layers as functions, if the fast path fits.

        Decided once per model (:func:`~radial_ibvs_agents.learned.files.mean_action.actor_layers`).
        """
        from radial_ibvs_agents.learned.files.mean_action import actor_layers

        policy = getattr(self.model, "policy", self.model)
        cached: tuple[Any, list[Any] | None] | None = getattr(self, "_fast", None)
        if cached is None or cached[0] is not policy:
            cached = self._fast = (policy, actor_layers(policy))
            if cached[1] is not None:
                policy.set_training_mode(False)
        return None if cached[1] is None else (policy, cached[1])


def shipped_models() -> list[str]:
    """Names of the models shipped with the package (``learned/models/<name>/`` in it)."""
    if not MODELS_DIR.is_dir():
        return []
    return sorted(p.name for p in MODELS_DIR.iterdir() if has_policy_files(p))


def is_bare_name(name: str | Path) -> bool:
    """Whether ``name`` is a bare name (``my-model``), not a path (``./my-model``, ``a/b``)."""
    text = str(name)
    return (
        not isinstance(name, Path)
        and "/" not in text
        and "\\" not in text
        and text
        not in (
            ".",
            "..",
        )
    )


def resolve_model(name_or_path: str | Path) -> Path:
    """Return the directory (or ``.zip``) that a model name or path means.

    A bare name (no ``/``) is a shipped model's name, and only that: a folder of the current
    directory is loaded by a path (``./my-model``). So a folder that happens to be named like
    a shipped model never replaces it, and a bare name never loads a folder silently.

    Raises
    ------
    ValueError
        For an unknown name (listing the shipped ones; pointing at ``./name`` when such a
        folder exists) or a path that does not exist.
    """
    label = repr(str(name_or_path))[:200]
    if is_bare_name(name_or_path):
        if str(name_or_path) in shipped_models():
            return MODELS_DIR / str(name_or_path)
        hint = (
            f"; to load the folder of that name, give its path: ./{name_or_path}"
            if Path(name_or_path).exists()
            else ""
        )
        raise ValueError(f"unknown model {label}: not a shipped model {shipped_models()}{hint}")
    path = Path(name_or_path)
    if not path.exists():
        raise ValueError(f"model {label}: no such file or directory")
    return path


#: why a ``model.zip`` alone is refused, and how to opt in
_PICKLE_WARNING = (
    "a stable-baselines3 model.zip keeps part of its data as pickled Python objects, which "
    "run code when loaded, so it is not loaded by default. If you trust where it came from, "
    "load it with radial_ibvs_agents.load(path, trust_pickle=True) "
    "(on the command line: --trust-model), "
    "or convert it once with radial_ibvs_agents.learned.save_model_dir"
)


def load(name_or_path: str | Path, *, trust_pickle: bool = False) -> Any:
    """Load a shipped model by name (e.g. ``"dagger-student"``) or a model directory.

    A model directory holds ``policy.safetensors`` and ``policy.json`` (the policy's weights and its
    description: :mod:`radial_ibvs_agents.learned.files.model_files`), ``metadata.json`` and, if
    training normalised observations, ``normalization.npz``: nothing in them can run code. A
    stable-baselines3 ``model.zip`` beside them is never read. A directory with only a ``model.zip``
    (or the path of a ``.zip``) is refused unless ``trust_pickle`` is set.

    Parameters
    ----------
    name_or_path
        A name from :func:`shipped_models`, or the path of a model directory (what
        ``radial-ibvs train`` writes; ``./name`` for one in the current directory: a bare name
        is always a shipped model's), or of a ``model.zip`` inside one.
    trust_pickle
        Allow loading a stable-baselines3 ``model.zip`` through its pickles, where the
        directory has no ``policy.safetensors``: only for files from a source you trust.

    Returns
    -------
    LearnedPolicy, radial_ibvs_agents.learned.networks.history.HistoryPolicy or
    radial_ibvs_agents.learned.networks.residual.ResidualPolicy
        A ``HistoryPolicy`` when the metadata has a ``history`` entry (the model sees the last
        frames; the policy keeps them in its ``state``), a ``ResidualPolicy`` when it has a
        ``residual`` entry (a correction to an analytic policy, which it builds too).

    Raises
    ------
    ValueError
        For an unknown name (the message lists the shipped ones), a missing or corrupt file,
        or a pickled model without ``trust_pickle``.
    """
    path = resolve_model(name_or_path)
    label = repr(str(name_or_path))[:200]
    zipped = path.suffix == ".zip"
    directory = path.parent if zipped else path
    meta_path = directory / "metadata.json"
    zip_path = path if zipped else directory / "model.zip"
    if not has_policy_files(directory) and not meta_path.exists() and zip_path.is_file():
        # a model.zip saved by stable-baselines3 itself: only when trusted
        if not trust_pickle:
            raise ValueError(f"model {label}: refusing to load {zip_path}: {_PICKLE_WARNING}")
        metadata: Any = {"algo": algo_of_zip(zip_path, label)}
    elif not meta_path.is_file():
        raise ValueError(f"model {label}: {meta_path} is missing")
    else:
        try:
            metadata = read_json(meta_path, directory)  # bounded: size, depth, inside the folder
        except ValueError as error:
            raise ValueError(f"model {label}: {error}") from None
    if not isinstance(metadata, dict):
        raise ValueError(f"model {label}: {meta_path} is corrupt: not a JSON object")
    for key in ("env_kwargs", "history", "residual"):
        if metadata.get(key) is not None and not isinstance(metadata[key], dict):
            raise ValueError(f"model {label}: {meta_path}: {key} must be an object")
    if "env_id" in metadata:
        check_env_id(metadata["env_id"], f"{meta_path}: env_id")
    if not zipped and has_policy_files(directory):
        try:
            model, description = load_policy(directory)
        except ValueError as error:
            raise ValueError(f"model {label}: {error}") from None
        if metadata.get("algo", description["algo"]) != description["algo"]:
            raise ValueError(
                f"model {label}: {meta_path} says algo {str(metadata.get('algo'))[:40]!r}, "
                f"{directory / DESCRIPTION} says {description['algo']!r}"
            )
    else:
        if not zip_path.is_file():
            raise ValueError(
                f"model {label}: {directory / WEIGHTS} and {directory / DESCRIPTION} are missing"
            )
        if not trust_pickle:
            raise ValueError(f"model {label}: refusing to load {zip_path}: {_PICKLE_WARNING}")
        model = load_sb3_zip(zip_path, metadata, label)
        goal_keys = {"observation", "achieved_goal", "desired_goal"}
        if "env_id" not in metadata and set(getattr(model.observation_space, "spaces", {})) == (
            goal_keys
        ):
            metadata["env_id"] = "RadialIBVS/ParkingGoal-v1"
    norm_path = directory / "normalization.npz"
    normalization = read_normalization(norm_path) if norm_path.is_file() else None
    name = str(name_or_path) if is_bare_name(name_or_path) else directory.name
    learned: Any = LearnedPolicy(model, metadata, normalization, name)
    if metadata.get("history") is not None:
        from radial_ibvs_agents.learned.networks.history import HistoryConfig, HistoryPolicy

        history = HistoryConfig.from_mapping(metadata["history"], f"{meta_path}: history")
        learned = HistoryPolicy(learned, history)
    if metadata.get("residual") is not None:
        from radial_ibvs_agents.learned.networks.residual import ResidualConfig, ResidualPolicy

        residual = ResidualConfig.from_mapping(metadata["residual"], f"{meta_path}: residual")
        return ResidualPolicy(learned, residual)
    return learned


def _rows(observation: Any, space: Any) -> int:
    """Return how many observations a (batched) observation holds (1 for one).

    A Dict observation is read by its first key; a Box one by its own shape.
    """
    spaces = getattr(space, "spaces", None)
    if isinstance(spaces, dict) and spaces:
        key, sub = next(iter(spaces.items()))
        value, shape = np.asarray(observation[key]), sub.shape
    else:
        value, shape = np.asarray(observation), getattr(space, "shape", None)
    if shape is None or value.ndim <= len(shape):
        return 1
    return int(value.shape[0])
