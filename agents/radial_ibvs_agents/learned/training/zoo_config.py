"""Agent hyper-parameters in rl-zoo3's YAML format, validated on load.

A config file has one section per env id, as rl-zoo3's ``hyperparams/<algo>.yml``
(``n_envs``, ``n_timesteps``, ``policy``, ``normalize``, ``policy_kwargs`` as a string, the
algorithm's keyword arguments, ``lin_<x>`` schedules), so ``python -m rl_zoo3.train
--gym-packages radial_ibvs_gym --conf-file <file>`` reads it too, and a ``radial_ibvs_gym``
section that rl-zoo3 ignores: the env's ``gym.make`` arguments and the evaluation settings.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from radial_ibvs_agents.learned.files.policy_size import check_net_arch
from radial_ibvs_agents.learned.networks import TRAIN_EXTRACTORS
from radial_ibvs_agents.learned.networks.residual import ResidualConfig
from radial_ibvs_agents.learned.training.curriculum import CurriculumConfig
from radial_ibvs_agents.learned.training.fine_tune import FineTuneConfig
from radial_ibvs_gym.config import read_yaml_with_base
from radial_ibvs_gym.limits import (
    MAX_BATCH_SIZE,
    MAX_BUFFER_SIZE,
    MAX_EPISODES,
    MAX_NUM_ENVS,
    MAX_ROLLOUT_SIZE,
)
from radial_ibvs_gym.registration import check_env_id

__all__ = ["TRAIN_EXTRACTORS", "TrainConfig", "load_train_config", "parse_kwargs_string"]

#: rl-zoo3's keys that are not the algorithm's keyword arguments
_ZOO_KEYS = {"n_envs", "n_timesteps", "policy", "normalize", "policy_kwargs", "env_wrapper"}
#: the feature extractors a training config may name (``radial_ibvs_gym.extractor``): the student's
#: (classes of :mod:`radial_ibvs_agents.learned.networks.extractors`), and the pose layer on
#: ``ParkingGoal-v1``'s goals for HER

_META_KEYS = {
    "env_kwargs", "eval_freq", "eval_episodes", "eval_seed", "residual", "curriculum", "fine_tune",
    "extractor",
}  # fmt: skip


@dataclass(frozen=True)
class TrainConfig:
    """A validated training configuration.

    Attributes
    ----------
    env_id
        The Gymnasium id (the section's name).
    n_envs
        Parallel envs.
    n_timesteps
        Total env steps.
    policy
        SB3 policy name (``MultiInputPolicy`` for the Dict observations).
    normalize
        ``VecNormalize`` keyword arguments, or ``None`` for no normalisation.
    policy_kwargs
        Policy keyword arguments (parsed from rl-zoo3's string form).
    algo_kwargs
        The algorithm's other keyword arguments (schedules already built).
    env_kwargs
        ``gym.make`` keyword arguments.
    eval_freq, eval_episodes, eval_seed
        Evaluation every ``eval_freq`` env steps on ``eval_episodes`` held-out episodes seeded
        from ``eval_seed``.
    residual
        Train a correction to an analytic policy
        (:class:`radial_ibvs_agents.learned.networks.residual.ResidualConfig`),
        or ``None`` for a policy from scratch.
    curriculum
        A reverse curriculum on the training envs' ``start_reach``
        (:class:`radial_ibvs_agents.learned.training.curriculum.CurriculumConfig`), or ``None``.
    fine_tune
        How a fine-tuning from a student starts
        (:class:`radial_ibvs_agents.learned.training.fine_tune. FineTuneConfig`), or ``None``; used
        only with ``init_from``.
    extractor
        ``None`` (SB3's ``CombinedExtractor`` on the normalised observation) or the name of one of
        the student's feature extractors
        (:data:`radial_ibvs_agents.learned.networks.TRAIN_EXTRACTORS`: ``landmark_pose`` adds the
        goal's pose solved from the bearings; ``goal_pose`` is the same on ``ParkingGoal-v1`` with
        ``goal_depths``, for HER); the keys it reads raw are left out of the normalisation.
    source
        The file and section it came from, and the raw section (for the model's metadata).
    """

    env_id: str
    n_envs: int
    n_timesteps: int
    policy: str
    normalize: dict[str, Any] | None
    policy_kwargs: dict[str, Any]
    algo_kwargs: dict[str, Any]
    env_kwargs: dict[str, Any]
    eval_freq: int = 25_000
    eval_episodes: int = 20
    eval_seed: int = 10_000
    residual: ResidualConfig | None = None
    curriculum: CurriculumConfig | None = None
    fine_tune: FineTuneConfig | None = None
    extractor: str | None = None
    source: dict[str, Any] = field(default_factory=dict)


def parse_kwargs_string(text: str, where: str) -> dict[str, Any]:
    """Parse rl-zoo3's ``"dict(key=value, ...)"`` strings safely (literals and ``nn.<Name>``).

    Parameters
    ----------
    text
        E.g. ``"dict(net_arch=[256, 256], activation_fn=nn.ReLU)"``.
    where
        Where it came from, for error messages.

    Raises
    ------
    ValueError
        If it is not a ``dict(...)`` call of literals and ``nn`` activation names.
    """
    import ast

    try:
        tree = ast.parse(text.strip(), mode="eval").body
    except SyntaxError as error:
        raise ValueError(f"{where}: cannot parse {text!r}: {error.msg}") from None
    if not (isinstance(tree, ast.Call) and isinstance(tree.func, ast.Name)):
        raise ValueError(f"{where}: expected 'dict(...)', got {text!r}")
    if tree.func.id != "dict" or tree.args:
        raise ValueError(f"{where}: expected 'dict(key=value, ...)', got {text!r}")
    out: dict[str, Any] = {}
    for keyword in tree.keywords:
        if keyword.arg is None:
            raise ValueError(f"{where}: '**' is not supported in {text!r}")
        out[keyword.arg] = _literal(keyword.value, where, text)
    return out


def _literal(node: Any, where: str, text: str) -> Any:
    import ast

    if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name):
        if node.value.id in ("nn", "th.nn", "torch.nn"):
            from torch import nn
            from torch.nn.modules import activation

            value = getattr(nn, node.attr, None)
            if not (
                isinstance(value, type)
                and issubclass(value, nn.Module)
                and value.__module__ == activation.__name__
            ):
                raise ValueError(
                    f"{where}: nn.{node.attr} is not an activation of torch.nn (nn.ReLU, "
                    f"nn.Tanh...), in {text!r}"
                )
            return value
    if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "dict":
        return parse_kwargs_string(ast.unparse(node), where)
    try:
        return ast.literal_eval(node)
    except ValueError:
        raise ValueError(
            f"{where}: only literals, dict(...) and nn.<Name> are allowed, got "
            f"{ast.unparse(node)!r} in {text!r}"
        ) from None


def _schedule(value: Any, where: str) -> Any:
    """rl-zoo3's ``lin_<x>``: a linear schedule from ``x`` to 0 over training."""
    if isinstance(value, str) and value.startswith("lin_"):
        try:
            start = float(value[4:])
        except ValueError:
            raise ValueError(f"{where}: bad linear schedule {value!r}") from None

        def linear(progress_remaining: float) -> float:
            return progress_remaining * start

        schedule: Callable[[float], float] = linear
        return schedule
    return value


#: the hyper-parameters checked before stable-baselines3 sees them: (kind, low, high), with
#: ``low`` included; kinds: "int" (whole numbers), "float" (numbers), "rate" (a number or a
#: ``lin_<x>`` schedule, already a function here)
_HYPERPARAMETERS: dict[str, tuple[str, float, float]] = {
    "n_steps": ("int", 1, MAX_ROLLOUT_SIZE),
    "batch_size": ("int", 1, MAX_BATCH_SIZE),
    "n_epochs": ("int", 1, 10_000),
    "buffer_size": ("int", 1, MAX_BUFFER_SIZE),
    "learning_starts": ("int", 0, 1 << 40),
    "gradient_steps": ("int", -1, 1 << 20),
    "policy_delay": ("int", 1, 1 << 20),
    "top_quantiles_to_drop_per_net": ("int", 0, 1 << 10),
    "learning_rate": ("rate", 0.0, 10.0),
    "clip_range": ("rate", 1e-12, 1e6),
    "gamma": ("float", 0.0, 1.0),
    "gae_lambda": ("float", 0.0, 1.0),
    "tau": ("float", 0.0, 1.0),
    "vf_coef": ("float", 0.0, 1e6),
    "max_grad_norm": ("float", 1e-12, 1e12),
}


#: the hyper-parameters bounded by a limit of :mod:`radial_ibvs_gym.limits`, and its name
_LIMITS = {
    "n_steps": "MAX_ROLLOUT_SIZE",
    "batch_size": "MAX_BATCH_SIZE",
    "buffer_size": "MAX_BUFFER_SIZE",
}


def _check_hyperparameter(key: str, value: Any, where: str) -> Any:
    """Return a known hyper-parameter checked (whole numbers as ``int``), before SB3 sees it.

    Raises
    ------
    ValueError
        For the wrong type or range, naming the key and the value.
    """
    if key not in _HYPERPARAMETERS:
        return value
    kind, low, high = _HYPERPARAMETERS[key]
    if kind == "rate" and callable(value):
        return value  # a lin_<x> schedule, checked when parsed
    number = isinstance(value, int | float) and not isinstance(value, bool)
    whole = number and (kind != "int" or float(value).is_integer())
    if not (whole and low <= value <= high):
        what = "an integer" if kind == "int" else "a number"
        what += " or a 'lin_<x>' schedule" if kind == "rate" else ""
        bounds = f"[{low:g}, {high:,}]" if kind == "int" else f"[{low:g}, {high:g}]"
        named = f" ({_LIMITS[key]})" if key in _LIMITS else ""
        raise ValueError(f"{where}.{key} must be {what} in {bounds}{named}, got {value!r}")
    return int(value) if kind == "int" else value


def _replay_buffer_class(name: Any, where: str) -> type:
    """rl-zoo3's ``replay_buffer_class: HerReplayBuffer`` (the one buffer name it takes)."""
    if name != "HerReplayBuffer":
        raise ValueError(f"{where} must be 'HerReplayBuffer', got {name!r}")
    from stable_baselines3 import HerReplayBuffer

    return HerReplayBuffer


def _positive_int(
    section: Mapping[str, Any],
    key: str,
    default: int,
    where: str,
    limit: tuple[str, int] | None = None,
) -> int:
    value = section.get(key, default)
    if isinstance(value, float) and value.is_integer():
        value = int(value)
    if not isinstance(value, int) or isinstance(value, bool) or value <= 0:
        raise ValueError(f"{where}.{key} must be a positive integer, got {value!r}")
    if limit is not None and value > limit[1]:
        raise ValueError(f"{where}.{key} = {value} exceeds {limit[0]} = {limit[1]}")
    return value


def _residual(value: Any, where: str) -> ResidualConfig | None:
    if value is None:
        return None
    if not isinstance(value, Mapping):
        raise ValueError(f"{where} must be a mapping (base, scale), got {value!r}")
    return ResidualConfig.from_mapping(value, where)


def load_train_config(path: Path | str, env_id: str | None = None) -> TrainConfig:
    """Load and validate a training configuration.

    Parameters
    ----------
    path
        The YAML file (rl-zoo3 format plus the ``radial_ibvs_gym`` section).
    env_id
        The section to use; default: the file's only env section.

    Raises
    ------
    ValueError
        For a missing file or section, an unknown key of the ``radial_ibvs_gym`` section, or a
        bad value (the message names it).
    """
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"config file {str(path)!r} not found")
    data = read_yaml_with_base(path)  # bounded: no aliases, limited size and depth; base: overlays
    if not isinstance(data, Mapping):
        raise ValueError(f"{path}: expected a mapping of env ids to hyper-parameters")
    meta = dict(data.get("radial_ibvs_gym") or {})
    sections = [k for k in data if k != "radial_ibvs_gym"]
    if env_id is None:
        if len(sections) != 1:
            raise ValueError(f"{path}: several env sections {sections}; choose one with --env-id")
        env_id = sections[0]
    check_env_id(env_id, f"{path}: the section name")
    if env_id not in data:
        raise ValueError(f"{path}: no section for env id {env_id!r}; found {sections}")
    section = dict(data[env_id] or {})
    where = f"{path.name}[{env_id!r}]"
    unknown = sorted(set(meta) - _META_KEYS)
    if unknown:
        raise ValueError(f"{path.name}[radial_ibvs_gym]: unknown key(s) {unknown}")
    if "env_wrapper" in section:
        raise ValueError(f"{where}.env_wrapper is not supported; use env_kwargs instead")
    normalize = section.get("normalize", False)
    if isinstance(normalize, str):
        normalize = parse_kwargs_string(normalize, f"{where}.normalize")
    elif normalize is True:
        normalize = {}
    elif normalize is False:
        normalize = None
    else:
        raise ValueError(f"{where}.normalize must be a bool or 'dict(...)', got {normalize!r}")
    policy_kwargs = section.get("policy_kwargs", {})
    if isinstance(policy_kwargs, str):
        policy_kwargs = parse_kwargs_string(policy_kwargs, f"{where}.policy_kwargs")
    if not isinstance(policy_kwargs, Mapping):
        raise ValueError(f"{where}.policy_kwargs must be 'dict(...)', got {policy_kwargs!r}")
    if "net_arch" in policy_kwargs:
        check_net_arch(policy_kwargs["net_arch"], f"{where}.policy_kwargs.net_arch")
    algo_kwargs = {
        key: _schedule(value, f"{where}.{key}")
        for key, value in section.items()
        if key not in _ZOO_KEYS
    }
    if "replay_buffer_class" in algo_kwargs:
        algo_kwargs["replay_buffer_class"] = _replay_buffer_class(
            algo_kwargs["replay_buffer_class"], f"{where}.replay_buffer_class"
        )
    if isinstance(algo_kwargs.get("replay_buffer_kwargs"), str):
        algo_kwargs["replay_buffer_kwargs"] = parse_kwargs_string(
            algo_kwargs["replay_buffer_kwargs"], f"{where}.replay_buffer_kwargs"
        )
    for key, value in algo_kwargs.items():
        if isinstance(value, float) and not math.isfinite(value):
            raise ValueError(f"{where}.{key} must be finite, got {value!r}")
        algo_kwargs[key] = _check_hyperparameter(key, value, where)
    n_envs = _positive_int(section, "n_envs", 1, where, ("MAX_NUM_ENVS", MAX_NUM_ENVS))
    if n_envs * algo_kwargs.get("n_steps", 1) > MAX_ROLLOUT_SIZE:
        raise ValueError(
            f"{where}: n_envs * n_steps = {n_envs} * {algo_kwargs['n_steps']} transitions per "
            f"rollout exceed MAX_ROLLOUT_SIZE = {MAX_ROLLOUT_SIZE}"
        )
    env_kwargs = meta.get("env_kwargs") or {}
    if not isinstance(env_kwargs, Mapping):
        raise ValueError(f"{path.name}[radial_ibvs_gym].env_kwargs must be a mapping")
    return TrainConfig(
        env_id=env_id,
        n_envs=n_envs,
        n_timesteps=_positive_int(section, "n_timesteps", 1_000_000, where),
        policy=str(section.get("policy", "MultiInputPolicy")),
        normalize=normalize,
        policy_kwargs=dict(policy_kwargs),
        algo_kwargs=algo_kwargs,
        env_kwargs=dict(env_kwargs),
        eval_freq=_positive_int(meta, "eval_freq", 25_000, f"{path.name}[radial_ibvs_gym]"),
        eval_episodes=_positive_int(
            meta,
            "eval_episodes",
            20,
            f"{path.name}[radial_ibvs_gym]",
            ("MAX_EPISODES", MAX_EPISODES),
        ),
        eval_seed=int(meta.get("eval_seed", 10_000)),
        residual=_residual(meta.get("residual"), f"{path.name}[radial_ibvs_gym].residual"),
        curriculum=None
        if meta.get("curriculum") is None
        else CurriculumConfig.from_mapping(
            meta["curriculum"], f"{path.name}[radial_ibvs_gym].curriculum"
        ),
        fine_tune=None
        if meta.get("fine_tune") is None
        else FineTuneConfig.from_mapping(
            meta["fine_tune"], f"{path.name}[radial_ibvs_gym].fine_tune"
        ),
        extractor=_extractor(meta.get("extractor"), f"{path.name}[radial_ibvs_gym].extractor"),
        source={"file": str(path), "env_id": env_id, "section": section, "meta": meta},
    )


def _extractor(value: Any, where: str) -> str | None:
    """Validate the ``extractor:`` entry: ``None`` or a name of the student's extractors."""
    if value is None:
        return None
    if not isinstance(value, str) or value not in TRAIN_EXTRACTORS:
        raise ValueError(f"{where} must be one of {list(TRAIN_EXTRACTORS)} or null, got {value!r}")
    return value
