"""Trained models as policies: load a saved (or shipped) model with its observation statistics.

A model directory holds ``model.zip`` (stable-baselines3), ``normalization.npz`` (the
``VecNormalize`` observation statistics, if training normalised observations) and
``metadata.json`` (algorithm, env id and ``gym.make`` arguments, seed, command, git revision,
training figures). :func:`load` returns a :class:`LearnedPolicy` with the same ``predict`` as
every other policy here, normalising observations exactly as training did.
"""

from __future__ import annotations

import json
import zipfile
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["MODELS_DIR", "LearnedPolicy", "load", "shipped_models"]

#: where the shipped models live (inside the package, so wheels carry them)
MODELS_DIR = Path(__file__).resolve().parent / "models"


class LearnedPolicy:
    """A trained stable-baselines3 model behind the common ``predict`` interface.

    Parameters
    ----------
    model
        The SB3 model.
    metadata
        The model's ``metadata.json`` (``env_kwargs`` in particular).
    normalization
        Observation statistics: ``{key: (mean, var)}``, plus ``clip_obs`` and ``epsilon``;
        ``None`` when training did not normalise observations.
    name
        The name it was loaded by.
    """

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
        """Raise a ``ValueError`` naming the difference if ``space`` is not the model's."""
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

    def _normalise(self, observation: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        if self.normalization is None:
            return observation
        clip, eps = self.normalization["clip_obs"], self.normalization["epsilon"]
        out = {}
        for key in self.model.observation_space.spaces:
            value = np.asarray(observation[key], dtype=np.float32)
            if key in self.normalization["stats"]:
                mean, var = self.normalization["stats"][key]
                value = np.clip((value - mean) / np.sqrt(var + eps), -clip, clip)
            out[key] = value.astype(np.float32)
        return out

    def predict(
        self,
        observation: dict[str, np.ndarray],
        state: Any = None,
        episode_start: np.ndarray | None = None,
        deterministic: bool = True,
    ) -> tuple[np.ndarray, Any]:
        """Action(s) for one observation or a batch, as stable-baselines3's ``predict``.

        Raises
        ------
        KeyError
            If the observation lacks a key the model was trained on (the message names the
            ``gym.make`` arguments to use).
        """
        missing = sorted(set(self.model.observation_space.spaces) - set(observation))
        if missing:
            raise KeyError(
                f"{self.name} needs observation keys {missing}: make the env with {self.env_kwargs}"
            )
        action, state = self.model.predict(
            self._normalise(observation), state, episode_start, deterministic
        )
        return np.asarray(action, dtype=np.float32), state


def shipped_models() -> list[str]:
    """Names of the models shipped with the package (``agents/learned/models/<name>/``)."""
    if not MODELS_DIR.is_dir():
        return []
    return sorted(p.name for p in MODELS_DIR.iterdir() if (p / "model.zip").is_file())


def load(name_or_path: str | Path) -> Any:
    """Load a shipped model by name (e.g. ``"ppo-paper-sim"``) or a model directory.

    Parameters
    ----------
    name_or_path
        A name from :func:`shipped_models`, or a directory with ``model.zip`` and
        ``metadata.json`` (what ``radial-ibvs train`` writes), or a ``model.zip`` inside one.

    Returns
    -------
    LearnedPolicy or agents.learned.residual.ResidualPolicy
        The latter when the metadata has a ``residual`` entry (a correction to an analytic
        policy, which it builds too).

    Raises
    ------
    ValueError
        For an unknown name (the message lists the shipped ones), a missing or corrupt file.
    """
    path = Path(name_or_path)
    if not path.exists():
        if str(name_or_path) in shipped_models():
            path = MODELS_DIR / str(name_or_path)
        else:
            raise ValueError(
                f"unknown model {str(name_or_path)!r}: neither a shipped model "
                f"{shipped_models()} nor an existing path"
            )
    directory, zip_path = (
        (path.parent, path) if path.suffix == ".zip" else (path, path / "model.zip")
    )
    meta_path = directory / "metadata.json"
    for required in (zip_path, meta_path):
        if not required.is_file():
            raise ValueError(f"model {str(name_or_path)!r}: {required} is missing")
    try:
        metadata = json.loads(meta_path.read_text())
    except json.JSONDecodeError as error:
        raise ValueError(f"model {str(name_or_path)!r}: {meta_path} is corrupt: {error}") from None
    from agents.learned.training import ALGOS

    algo = metadata.get("algo")
    if algo not in ALGOS:
        raise ValueError(f"model {str(name_or_path)!r}: unknown algo {algo!r} in {meta_path}")
    # off-policy models: no replay buffer to predict (a HER buffer would even need the env)
    inference: dict[str, Any] | None = (
        {"replay_buffer_class": None, "replay_buffer_kwargs": {}, "buffer_size": 1}
        if algo != "ppo"
        else None
    )
    try:
        model = ALGOS[algo].load(zip_path, device="cpu", custom_objects=inference)
    except (zipfile.BadZipFile, ValueError, KeyError, RuntimeError, EOFError) as error:
        raise ValueError(f"model {str(name_or_path)!r}: {zip_path} is corrupt: {error}") from None
    norm_path = directory / "normalization.npz"
    normalization = _load_normalization(norm_path) if norm_path.is_file() else None
    name = str(name_or_path) if not Path(name_or_path).exists() else directory.name
    learned = LearnedPolicy(model, metadata, normalization, name)
    if metadata.get("residual") is not None:
        from agents.learned.residual import ResidualConfig, ResidualPolicy

        residual = ResidualConfig.from_mapping(metadata["residual"], f"{meta_path}: residual")
        return ResidualPolicy(learned, residual)
    return learned


def _load_normalization(path: Path) -> dict[str, Any]:
    try:
        with np.load(path) as data:
            stats = {
                key[len("mean/") :]: (data[key], data["var/" + key[len("mean/") :]])
                for key in data.files
                if key.startswith("mean/")
            }
            return {
                "stats": stats,
                "clip_obs": float(data["clip_obs"]),
                "epsilon": float(data["epsilon"]),
            }
    except (OSError, KeyError, ValueError, zipfile.BadZipFile) as error:
        raise ValueError(f"{path} is corrupt: {error}") from None
