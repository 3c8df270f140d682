"""Model files without pickles: an SB3 policy's weights as safetensors, described in JSON.

stable-baselines3's ``model.zip`` keeps some of its ``data`` as cloudpickled objects, which
run code when they are loaded. A model directory of this project holds instead:

- ``policy.safetensors``: the policy's ``state_dict`` (the ``safetensors`` format: tensors
  and nothing else);
- ``policy.json``: what rebuilds the policy around those weights: the algorithm, the policy
  class and its keyword arguments by name, the observation and action spaces, and the
  SHA-256 of the weights file.

:func:`load_policy` rebuilds the SB3 policy from these two files. Classes are named, never
pickled, and resolved only among an allow-list: the policy classes of the algorithm, the
activations and optimizers of ``torch``, and the feature extractors of stable-baselines3.
Nothing read here can run code.
"""

from __future__ import annotations

import io
import json
import math
import os
import zipfile
from pathlib import Path
from typing import Any

import numpy as np

from radial_ibvs_agents.io import write_atomic
from radial_ibvs_agents.learned.files.former_paths import current_name
from radial_ibvs_agents.learned.files.policy_size import (
    MAX_SPACE_ELEMENTS,
    check_finite_weights,
    check_policy_size,
    check_weight_types,
    read_weight_shapes,
)
from radial_ibvs_agents.untrusted import check_archive, read_json, sha256_file

__all__ = [
    "DESCRIPTION",
    "WEIGHTS",
    "algorithms",
    "has_policy_files",
    "load_policy",
    "read_normalization",
    "save_normalization",
    "save_policy",
    "space_from_json",
    "space_to_json",
]

WEIGHTS = "policy.safetensors"
DESCRIPTION = "policy.json"
FORMAT = "radial_ibvs_gym.sb3-policy"
FORMAT_VERSION = 1
#: the policy's constructor arguments that are not stored (rebuilt, or not needed to act)
_NOT_STORED = {"observation_space", "action_space", "lr_schedule"}


def algorithms() -> dict[str, Any]:
    """Return the SB3 algorithms a model may name, by the name ``policy.json`` stores.

    ``ppo``, ``a2c``, ``sac`` and ``td3`` (stable-baselines3); ``tqc`` and ``recurrent_ppo``
    (``RecurrentPPO``) when sb3-contrib is installed (``pip install 'radial_ibvs_gym[contrib]'``).
    """
    from stable_baselines3 import A2C, PPO, SAC, TD3

    found: dict[str, Any] = {"ppo": PPO, "a2c": A2C, "sac": SAC, "td3": TD3}
    try:
        from sb3_contrib import TQC, RecurrentPPO
    except ImportError:
        return found
    return {**found, "tqc": TQC, "recurrent_ppo": RecurrentPPO}


def has_policy_files(directory: Path) -> bool:
    """Whether ``directory`` holds ``policy.safetensors`` and ``policy.json``."""
    return (directory / WEIGHTS).is_file() and (directory / DESCRIPTION).is_file()


def _name(cls: type) -> str:
    return f"{cls.__module__}.{cls.__qualname__}"


def _policy_classes(algo: str) -> dict[str, type]:
    """Return the policy classes of the algorithm (``policy_aliases``) by ``module.qualname``."""
    return {_name(c): c for c in algorithms()[algo].policy_aliases.values()}


def _allowed_classes() -> dict[str, type]:
    """Return the classes a policy's keyword arguments may name, by ``module.qualname``."""
    import torch
    from stable_baselines3.common import torch_layers

    from radial_ibvs_agents.learned.networks import extractors

    groups = (
        (vars(torch.nn.modules.activation).values(), torch.nn.Module),
        (vars(torch.optim).values(), torch.optim.Optimizer),
        (vars(torch_layers).values(), torch_layers.BaseFeaturesExtractor),
        (vars(extractors).values(), torch_layers.BaseFeaturesExtractor),  # this project's
    )
    return {
        _name(obj): obj
        for members, base in groups
        for obj in members
        if isinstance(obj, type) and issubclass(obj, base)
    }


def _encode(value: Any, where: str, allowed: dict[str, type]) -> Any:
    if isinstance(value, type):
        name = _name(value)
        if name not in allowed:
            raise ValueError(
                f"{where} = {name} cannot be stored without a pickle: only torch activations "
                "and optimizers, stable-baselines3 feature extractors and policy classes can"
            )
        return {"__class__": name}
    if isinstance(value, dict):
        return {str(k): _encode(v, f"{where}[{k!r}]", allowed) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_encode(v, f"{where}[{i}]", allowed) for i, v in enumerate(value)]
    if isinstance(value, bool | int | float | str) or value is None:
        return value
    raise ValueError(f"{where} = {type(value).__name__} cannot be stored without a pickle")


def _decode(value: Any, where: str, allowed: dict[str, type]) -> Any:
    if isinstance(value, dict):
        if set(value) == {"__class__"}:
            name = value["__class__"]
            if isinstance(name, str):
                name = current_name(name)  # a model saved under a former module path
            if name not in allowed:
                raise ValueError(f"{where}: class {str(name)[:80]!r} is not allowed")
            return allowed[name]
        return {k: _decode(v, f"{where}[{k!r}]", allowed) for k, v in value.items()}
    if isinstance(value, list):
        return [_decode(v, f"{where}[{i}]", allowed) for i, v in enumerate(value)]
    return value


def _numbers(array: np.ndarray) -> Any:
    """Return an array as nested lists, non-finite values as strings (strict JSON)."""
    flat = [v if np.isfinite(v) else str(v) for v in array.astype(np.float64).ravel().tolist()]
    return np.array(flat, dtype=object).reshape(array.shape).tolist()


def _bound(array: np.ndarray) -> Any:
    """Return a Box's bound: one number where every element is the same (an image's 0 or 255)."""
    flat = np.asarray(array).ravel()
    if flat.size and np.all(flat == flat[0]):
        return _numbers(flat[:1])[0]
    return _numbers(np.asarray(array))


def space_to_json(space: Any) -> dict[str, Any]:
    """Describe a Gymnasium ``Box``, ``Discrete`` or ``Dict`` space as JSON values."""
    from gymnasium import spaces

    if isinstance(space, spaces.Dict):
        return {"type": "Dict", "spaces": {k: space_to_json(s) for k, s in space.spaces.items()}}
    if isinstance(space, spaces.Box):
        return {
            "type": "Box",
            "shape": list(space.shape),
            "dtype": str(space.dtype),
            "low": _bound(space.low),
            "high": _bound(space.high),
        }
    if isinstance(space, spaces.Discrete):
        return {"type": "Discrete", "n": int(space.n), "start": int(space.start)}
    raise ValueError(f"a {type(space).__name__} space cannot be described (Box, Discrete, Dict)")


def space_from_json(data: Any, where: str = "space") -> Any:
    """Rebuild a space described by :func:`space_to_json`.

    Raises
    ------
    ValueError
        For a description that is not one, naming where.
    """
    from gymnasium import spaces

    try:
        kind = data["type"]
        if kind == "Dict":
            return spaces.Dict(
                {str(k): space_from_json(v, f"{where}[{k!r}]") for k, v in data["spaces"].items()}
            )
        if kind == "Box":
            dtype = np.dtype(data["dtype"])
            if dtype.kind not in "fiu":
                raise ValueError(f"dtype {dtype} is not numeric")
            shape = tuple(int(n) for n in data["shape"])
            size = math.prod(shape)
            if any(n < 0 for n in shape) or size > MAX_SPACE_ELEMENTS:  # before any allocation
                raise ValueError(
                    f"shape {shape!r:.80}: at most MAX_SPACE_ELEMENTS = {MAX_SPACE_ELEMENTS} "
                    "numbers, none negative"
                )
            # a bound is an array of the shape, or one number for every element
            low = _bound_from(data["low"], shape)
            high = _bound_from(data["high"], shape)
            return spaces.Box(low.astype(dtype), high.astype(dtype), shape, dtype)
        if kind == "Discrete":
            return spaces.Discrete(int(data["n"]), start=int(data["start"]))
    except (KeyError, TypeError, ValueError, AttributeError) as error:
        raise ValueError(f"{where}: not a space description ({error})") from None
    raise ValueError(f"{where}: unknown space type {str(kind)[:40]!r}")


def _bound_from(value: Any, shape: tuple[int, ...]) -> np.ndarray:
    bound = np.array(value, dtype=np.float64)
    if bound.ndim == 0:
        return np.full(shape, float(bound))
    return bound.reshape(shape)


def _sha256(path: Path) -> str:
    return sha256_file(path, None)


def save_policy(model: Any, directory: Path | str, algo: str) -> list[Path]:
    """Write an SB3 model's policy as ``policy.safetensors`` and ``policy.json``.

    Parameters
    ----------
    model
        A stable-baselines3 algorithm (``PPO``, ``SAC``) or its ``policy``.
    directory
        The model directory (created).
    algo
        The algorithm's name, a key of :func:`algorithms`.

    Returns
    -------
    list of pathlib.Path
        The two files written.

    Raises
    ------
    ValueError
        If a constructor argument of the policy cannot be described without a pickle.
    """
    from safetensors.torch import save_model

    policy = getattr(model, "policy", model)
    out = Path(directory)
    out.mkdir(parents=True, exist_ok=True)
    allowed = _allowed_classes()
    params = policy._get_constructor_parameters()
    kwargs = {k: v for k, v in params.items() if k not in _NOT_STORED}
    weights = out / WEIGHTS
    partial = weights.with_name(weights.name + ".partial")
    save_model(policy, str(partial))
    mask = os.umask(0)
    os.umask(mask)
    os.chmod(partial, 0o666 & ~mask)  # the usual permissions (safetensors makes it 0600)
    partial.replace(weights)
    description = {
        "format": FORMAT,
        "format_version": FORMAT_VERSION,
        "algo": algo,
        "policy_class": _encode(type(policy), "policy_class", _policy_classes(algo)),
        "policy_kwargs": _encode(kwargs, "policy_kwargs", allowed),
        "observation_space": space_to_json(policy.observation_space),
        "action_space": space_to_json(policy.action_space),
        "weights_sha256": _sha256(weights),
    }
    text = json.dumps(description, indent=1, allow_nan=False) + "\n"
    return [weights, write_atomic(out / DESCRIPTION, text)]


def _no_learning(_progress: float) -> float:
    return 0.0


def load_policy(directory: Path | str) -> tuple[Any, dict[str, Any]]:
    """Rebuild the SB3 policy of a model directory from its safetensors and JSON files.

    Parameters
    ----------
    directory
        A directory holding ``policy.safetensors`` and ``policy.json``.

    Returns
    -------
    tuple
        The policy (``stable_baselines3.common.policies.BasePolicy``, on the CPU, in
        evaluation mode) and the description read from ``policy.json``.

    Raises
    ------
    ValueError
        For a missing, corrupt or altered file (the weights must match the SHA-256 of the
        description), an unknown algorithm or a class outside the allow-list.
    """
    from safetensors import SafetensorError
    from safetensors.torch import load_model

    folder = Path(directory)
    described, weights = folder / DESCRIPTION, folder / WEIGHTS
    for required in (described, weights):
        if not required.is_file():
            raise ValueError(f"{required} is missing")
    description = read_json(described, folder)
    weights_sha256 = sha256_file(weights, folder)  # size-bounded and inside the folder
    try:
        if not isinstance(description, dict):
            raise ValueError("not a JSON object")
        if description.get("format") != FORMAT:
            raise ValueError(f"format {str(description.get('format'))[:60]!r} is not {FORMAT!r}")
        version = description.get("format_version")
        if type(version) is not int or version != FORMAT_VERSION:  # not true, not 1.0
            raise ValueError(f"format_version {description.get('format_version')!r} is unknown")
        algo = description["algo"]
        if algo not in algorithms():
            raise ValueError(f"unknown algo {str(algo)[:40]!r}; valid: {sorted(algorithms())}")
        policy_class = _decode(description["policy_class"], "policy_class", _policy_classes(algo))
        kwargs = _decode(description["policy_kwargs"], "policy_kwargs", _allowed_classes())
        if not isinstance(kwargs, dict) or not isinstance(policy_class, type):
            raise ValueError("policy_class or policy_kwargs is malformed")
        observation_space = space_from_json(description["observation_space"], "observation_space")
        action_space = space_from_json(description["action_space"], "action_space")
    except (UnicodeDecodeError, KeyError, TypeError, AttributeError) as e:
        raise ValueError(f"{described} is corrupt: {type(e).__name__}: {str(e)[:200]}") from None
    except ValueError as error:
        raise ValueError(f"{described}: {str(error)[:300]}") from None
    if weights_sha256 != description.get("weights_sha256"):
        raise ValueError(f"{weights} does not match the SHA-256 in {described}")
    try:  # before anything is allocated: the description may ask for any size
        check_policy_size(kwargs, observation_space, action_space, read_weight_shapes(weights))
    except ValueError as error:
        raise ValueError(f"{described}: {str(error)[:300]}") from None
    try:
        policy = policy_class(observation_space, action_space, _no_learning, **kwargs)
    except (TypeError, ValueError) as error:
        raise ValueError(f"{described}: cannot build the policy: {str(error)[:300]}") from None
    check_weight_types(policy, weights)
    try:
        load_model(policy, str(weights), strict=True, device="cpu")
    except (SafetensorError, RuntimeError, ValueError, KeyError) as error:
        raise ValueError(f"{weights} is corrupt or does not fit: {str(error)[:300]}") from None
    check_finite_weights(policy, weights)
    policy.set_training_mode(False)
    return policy, description


def save_normalization(venv: Any, path: Path | str) -> Path:
    """Write the statistics of an SB3 ``VecNormalize`` as plain arrays (``.npz``, no pickle).

    Holds ``clip_obs``, ``epsilon``, and per observation key ``mean/KEY``, ``var/KEY`` and
    ``count/KEY``; with reward normalisation also ``ret_mean``, ``ret_var`` and
    ``ret_count`` (what resuming a training needs).
    """
    rms = venv.obs_rms
    arrays: dict[str, np.ndarray] = {
        "clip_obs": np.array(venv.clip_obs),
        "epsilon": np.array(venv.epsilon),
    }
    items = rms.items() if isinstance(rms, dict) else [("obs", rms)]
    for key, stats in items:
        arrays[f"mean/{key}"] = np.asarray(stats.mean, dtype=np.float32)
        arrays[f"var/{key}"] = np.asarray(stats.var, dtype=np.float32)
        arrays[f"count/{key}"] = np.array(float(stats.count))
    if getattr(venv, "norm_reward", False):
        ret = venv.ret_rms
        arrays["ret_mean"] = np.asarray(ret.mean, dtype=np.float64)
        arrays["ret_var"] = np.asarray(ret.var, dtype=np.float64)
        arrays["ret_count"] = np.array(float(ret.count))
    out = Path(path)
    buffer = io.BytesIO()
    np.savez(buffer, **arrays)  # type: ignore[arg-type]
    return write_atomic(out, buffer.getvalue())


def read_normalization(path: Path | str) -> dict[str, Any]:
    """Read :func:`save_normalization`'s ``.npz`` (plain arrays: ``np.load`` without pickles).

    Returns
    -------
    dict
        ``stats`` ``{key: (mean, var)}``, ``counts`` ``{key: count}`` (those saved; older files
        have none), ``clip_obs``, ``epsilon``, and ``ret`` ``(mean, var, count)`` or ``None``.

    Raises
    ------
    ValueError
        If the file is not such a file (naming it).
    """
    check_archive(path, Path(path).parent)  # a zip whose members inflate within bounds
    try:
        with np.load(path, allow_pickle=False) as data:
            keys = [k[len("mean/") :] for k in data.files if k.startswith("mean/")]
            read = {
                "stats": {k: (data[f"mean/{k}"], data[f"var/{k}"]) for k in keys},
                "counts": {k: float(data[f"count/{k}"]) for k in keys if f"count/{k}" in data},
                "clip_obs": float(data["clip_obs"]),
                "epsilon": float(data["epsilon"]),
                "ret": (
                    (data["ret_mean"], data["ret_var"], float(data["ret_count"]))
                    if "ret_mean" in data.files
                    else None
                ),
            }
    except (OSError, KeyError, ValueError, TypeError, zipfile.BadZipFile) as error:
        raise ValueError(f"{path} is corrupt: {str(error)[:300]}") from None
    return _check_statistics(path, read)


def _check_statistics(path: Path | str, read: dict[str, Any]) -> dict[str, Any]:
    """Refuse observation statistics that would normalise into NaN or infinity (naming the file).

    Raises
    ------
    ValueError
        For a mean or variance that is not finite, a negative variance, shapes that differ, or
        a ``clip_obs`` or ``epsilon`` that is not a positive number.
    """
    for key, (mean, var) in read["stats"].items():
        if np.shape(mean) != np.shape(var):
            raise ValueError(f"{path}: the statistics of {key!r} have shapes that differ")
        if not (np.isfinite(mean).all() and np.isfinite(var).all() and (var >= 0).all()):
            raise ValueError(f"{path}: the statistics of {key!r} are not finite, or negative")
    for name in ("clip_obs", "epsilon"):
        if not (math.isfinite(read[name]) and read[name] > 0):
            raise ValueError(f"{path}: {name} must be a positive number, got {read[name]!r}")
    return read
