"""The settings of DAgger (``learned.dagger.distill``): ``dagger_*.yaml`` configs.

The shipped ones are ``configs/agents/dagger_*.yaml``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from radial_ibvs_agents.analytic import make_analytic
from radial_ibvs_agents.learned.files.policy_size import check_net_arch
from radial_ibvs_agents.learned.networks import EXTRACTORS
from radial_ibvs_agents.learned.networks.extractors import ERROR_KEYS
from radial_ibvs_agents.learned.networks.history import HistoryConfig
from radial_ibvs_gym.config import read_yaml_with_base
from radial_ibvs_gym.limits import (
    MAX_BATCH_SIZE,
    MAX_DATASET_SIZE,
    MAX_EPISODES,
    MAX_NUM_ENVS,
    MAX_ROLLOUT_SIZE,
)
from radial_ibvs_gym.registration import check_env_id

__all__ = ["ACTIVATIONS", "EXTRACTORS", "PRIVILEGED", "DaggerConfig", "load_dagger_config"]

#: the student's activations, by name (torch.nn classes)
ACTIVATIONS = {"relu": "ReLU", "tanh": "Tanh"}
#: what the teacher needs added to the observation (the planner's poses and map)
PRIVILEGED = {"privileged": True, "privileged_map": True}


@dataclass(frozen=True)
class DaggerConfig:
    """A validated DAgger configuration (``configs/agents/dagger_*.yaml``).

    Attributes
    ----------
    env_id
        The Gymnasium id (with a native vector env).
    env_kwargs
        The student's ``gym.make`` arguments (its observation); the teacher's privileged
        keys are added for the rollouts only.
    teacher, teacher_kwargs
        The teacher's name in :data:`radial_ibvs_agents.analytic.ANALYTIC_POLICIES` and its
        arguments.
    n_envs
        Robots stepped together.
    rounds
        DAgger rounds.
    steps_per_round
        Env steps collected per round (all robots together).
    beta, beta_decay
        Probability that the teacher's action is executed in round 0, multiplied by
        ``beta_decay`` each round.
    updates_per_round, batch_size, learning_rate
        Gradient steps after each round, their batch size and Adam's step size.
    final_learning_rate
        ``None`` (the default): Adam's step size stays ``learning_rate``. A number: each
        round's gradient steps anneal it from ``learning_rate`` to this along a cosine
        (``torch.optim.lr_scheduler.CosineAnnealingLR``), so that each round ends on a fit
        below the noise floor of the constant step size.
    dataset_size
        The largest number of labelled states kept (older ones are replaced at random).
    net_arch
        Hidden layers of the student (and of its critic, for a later PPO fine-tuning).
    activation
        ``relu`` or ``tanh`` (SB3's PPO default).
    history
        The observation history the student gets (:class:`HistoryConfig`), or ``None``.
    error_keys
        The keys given to the network as direction and log-size
        (:class:`radial_ibvs_agents.learned.networks.extractors.ErrorScaleExtractor`); empty: raw,
        normalised.
    initial_dataset
        A Minari dataset of the teacher's episodes (``radial-ibvs collect --policy planner``,
        its directory): its states and actions join the labels before the first round.
    point_error
        Give the network the image error ``x_n - x_n*`` too, as direction and log-size.
    angle_keys
        Error keys that are wrapped angles, given continuously across the wrap (``angle_keys`` of
        :class:`radial_ibvs_agents.learned.networks.extractors.ErrorScaleExtractor`).
    extractor
        ``error_scale``
        (:class:`radial_ibvs_agents.learned.networks.extractors.ErrorScaleExtractor`),
        ``landmark_set``
        (:class:`radial_ibvs_agents.learned.networks.extractors.LandmarkSetExtractor`: the same
        features plus a learned encoding of the landmarks as a set) or ``landmark_pose``
        (:class:`radial_ibvs_agents.learned.networks.extractors.LandmarkPoseExtractor`: those plus
        the goal's pose solved from the image's bearings).
    pose_history
        With ``landmark_pose``: solve the goal's pose in each past frame of the ``history``
        too (which must hold ``points`` and ``visible``), so the network can filter it.
    balance_actions
        Weight each action component's squared error by the inverse of its label variance
        (the turn labels vary about 7 times less than the speed labels, and an unweighted fit
        shrinks the turns: students that circle the goal).
    relative_floor
        ``0`` (the default): the squared error of each action component. ``> 0``: the
        squared *relative* error, ``((a - label) / (|label| + relative_floor))^2``, so a
        label of a few hundredths (the teacher's final alignment near the goal: 10 deg of
        heading is a turn of 0.07 of the action range) is fit as closely, relatively, as a
        label of one far from it (an absolute fit leaves errors of about 0.05 everywhere, the
        size of those labels: the student stood still at the goal).
    aux_weight
        Weight of the auxiliary loss (the goal's pose in the robot frame, predicted from the
        actor's last hidden layer by a head used in training only; 0: none).
    eval_episodes, eval_seed
        Held-out episodes evaluated after each round (seeds ``eval_seed + i``).
    """

    env_id: str = "RadialIBVS/Parking-v0"
    env_kwargs: dict[str, Any] = field(default_factory=dict)
    teacher: str = "planner"
    teacher_kwargs: dict[str, Any] = field(default_factory=dict)
    n_envs: int = 256
    rounds: int = 20
    steps_per_round: int = 65_536
    beta: float = 1.0
    beta_decay: float = 0.5
    updates_per_round: int = 2_000
    batch_size: int = 4_096
    learning_rate: float = 1e-3
    final_learning_rate: float | None = None
    dataset_size: int = 2_000_000
    net_arch: tuple[int, ...] = (256, 256)
    activation: str = "relu"
    history: HistoryConfig | None = None
    error_keys: tuple[str, ...] = ERROR_KEYS
    point_error: bool = True
    extractor: str = "error_scale"
    angle_keys: tuple[str, ...] = ()
    pose_history: bool = False
    balance_actions: bool = True
    aux_weight: float = 1.0
    relative_floor: float = 0.0
    initial_dataset: str | None = None
    eval_episodes: int = 100
    eval_seed: int = 10_000
    source: dict[str, Any] = field(default_factory=dict)


_INTS = ("n_envs", "rounds", "steps_per_round", "updates_per_round", "batch_size")
_INTS_MORE = ("dataset_size", "eval_episodes", "eval_seed")
#: the upper bounds of the integers (:mod:`radial_ibvs_gym.limits`), by key, and their names
_INT_LIMITS = {
    "n_envs": ("MAX_NUM_ENVS", MAX_NUM_ENVS),
    "batch_size": ("MAX_BATCH_SIZE", MAX_BATCH_SIZE),
    "dataset_size": ("MAX_DATASET_SIZE", MAX_DATASET_SIZE),
    "eval_episodes": ("MAX_EPISODES", MAX_EPISODES),
}


def load_dagger_config(path: Path | str) -> DaggerConfig:
    """Read and validate a DAgger YAML file (its ``dagger:`` section).

    Raises
    ------
    ValueError
        For an unknown key or a bad value (the message names the key and the value).
    """
    data = read_yaml_with_base(path)  # a research overlay: base: and the changes
    section = data.get("dagger") if isinstance(data, Mapping) else None
    if not isinstance(section, Mapping):
        raise ValueError(f"{path}: expected a 'dagger:' mapping")
    where = f"{path}: dagger"
    known = {f for f in DaggerConfig.__dataclass_fields__ if f != "source"}
    unknown = sorted(set(section) - known)
    if unknown:
        raise ValueError(f"{where}: unknown key(s) {unknown}; valid: {sorted(known)}")
    values: dict[str, Any] = {}
    for key in (*_INTS, *_INTS_MORE):
        if key in section:
            value = section[key]
            if isinstance(value, float) and value.is_integer():
                value = int(value)
            least = 0 if key == "eval_seed" else 1
            if isinstance(value, bool) or not isinstance(value, int) or value < least:
                raise ValueError(f"{where}.{key} must be an integer >= {least}, got {value!r}")
            if key in _INT_LIMITS and value > _INT_LIMITS[key][1]:
                name, top = _INT_LIMITS[key]
                raise ValueError(f"{where}.{key} = {value} exceeds {name} = {top}")
            values[key] = value
    steps = values.get("steps_per_round", DaggerConfig.steps_per_round)
    if steps > MAX_ROLLOUT_SIZE:  # all robots together
        raise ValueError(
            f"{where}.steps_per_round = {steps} exceeds MAX_ROLLOUT_SIZE = {MAX_ROLLOUT_SIZE}"
        )
    for key, low, high in (("beta", 0.0, 1.0), ("beta_decay", 0.0, 1.0)):
        if key in section:
            value = section[key]
            if not isinstance(value, int | float) or not low <= value <= high:
                raise ValueError(f"{where}.{key} must be in [{low}, {high}], got {value!r}")
            values[key] = float(value)
    for key in ("point_error", "balance_actions", "pose_history"):
        if key in section:
            if not isinstance(section[key], bool):
                raise ValueError(f"{where}.{key} must be true or false, got {section[key]!r}")
            values[key] = section[key]
    for key in ("aux_weight", "relative_floor"):
        if key in section:
            value = section[key]
            if (
                isinstance(value, bool)
                or not isinstance(value, int | float)
                or not (math.isfinite(value) and value >= 0)
            ):
                raise ValueError(f"{where}.{key} must be a number >= 0, got {value!r}")
            values[key] = float(value)
    if "learning_rate" in section:
        value = section["learning_rate"]
        if not isinstance(value, int | float) or not (math.isfinite(value) and value > 0):
            raise ValueError(f"{where}.learning_rate must be a positive number, got {value!r}")
        values["learning_rate"] = float(value)
    if section.get("final_learning_rate") is not None:
        value = section["final_learning_rate"]
        top = values.get("learning_rate", DaggerConfig.learning_rate)
        if (
            isinstance(value, bool)
            or not isinstance(value, int | float)
            or not (math.isfinite(value) and 0 < value <= top)
        ):
            raise ValueError(
                f"{where}.final_learning_rate must be a positive number up to learning_rate "
                f"({top!r}), got {value!r}"
            )
        values["final_learning_rate"] = float(value)
    for key in ("env_kwargs", "teacher_kwargs"):
        if key in section:
            if not isinstance(section[key], Mapping):
                raise ValueError(f"{where}.{key} must be a mapping, got {section[key]!r}")
            values[key] = dict(section[key])
    if "env_id" in section:
        values["env_id"] = check_env_id(section["env_id"], f"{where}.env_id")
    for key in ("teacher", "initial_dataset"):
        if key in section:
            values[key] = str(section[key])
    if "extractor" in section:
        if section["extractor"] not in EXTRACTORS:
            raise ValueError(
                f"{where}.extractor must be one of {list(EXTRACTORS)}, got {section['extractor']!r}"
            )
        values["extractor"] = section["extractor"]
    if "activation" in section:
        if section["activation"] not in ACTIVATIONS:
            raise ValueError(
                f"{where}.activation must be one of {sorted(ACTIVATIONS)}, "
                f"got {section['activation']!r}"
            )
        values["activation"] = section["activation"]
    if "net_arch" in section:
        arch = section["net_arch"]
        if not isinstance(arch, list):
            raise ValueError(f"{where}.net_arch must be a list of positive integers, got {arch!r}")
        check_net_arch(arch, f"{where}.net_arch")
        values["net_arch"] = tuple(arch)
    if "error_keys" in section:
        keys = section["error_keys"]
        if not isinstance(keys, list) or not all(isinstance(k, str) for k in keys):
            raise ValueError(f"{where}.error_keys must be a list of key names, got {keys!r}")
        values["error_keys"] = tuple(keys)
    if "angle_keys" in section:
        keys = section["angle_keys"]
        if not isinstance(keys, list) or not all(
            k in values.get("error_keys", ERROR_KEYS) for k in keys
        ):
            raise ValueError(f"{where}.angle_keys must be a list of error keys, got {keys!r}")
        values["angle_keys"] = tuple(keys)
    if section.get("history") is not None:
        values["history"] = HistoryConfig.from_mapping(section["history"], f"{where}.history")
    if values.get("pose_history"):
        kept = values["history"].keys if "history" in values else ()
        if values.get("extractor") != "landmark_pose" or not {"points", "visible"} <= set(kept):
            raise ValueError(
                f"{where}.pose_history needs extractor: landmark_pose and a history whose keys "
                f"include points and visible, got extractor {values.get('extractor')!r} and "
                f"history keys {list(kept)}"
            )
    config = DaggerConfig(**values, source={"file": str(path), "dagger": dict(section)})
    make_analytic(config.teacher, **config.teacher_kwargs)  # the teacher's name and arguments
    return config
