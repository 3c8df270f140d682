"""The parking envs' arguments: one frozen, validated object shared by the scalar and vector envs.

:class:`ParkingConfig` holds every argument of ``RadialIBVS/Parking-v0`` (and of the envs built
on it) and what follows from them (the robot, the action scale, the landmark slots). It is
checked once, when it is made; the scalar env (:class:`~radial_ibvs_gym.envs.parking.ParkingEnv`)
and the native vector env (:class:`~radial_ibvs_gym.envs.parking_vector.ParkingVectorEnv`) both
read it, so they cannot disagree on an argument.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

import numpy as np

from radial_ibvs_gym.config import did_you_mean, short
from radial_ibvs_gym.envs.missed import MissedDetections
from radial_ibvs_gym.envs.rules import (
    PARK_HOLD_S,
    SUCCESS_TOLERANCES,
    TASK_TOLERANCE,
    park_hold_steps,
)
from radial_ibvs_gym.envs.slots import Slots
from radial_ibvs_gym.features import pair_indices
from radial_ibvs_gym.limits import (
    MAX_GOAL_FRAMES,
    MAX_HOLD_STEPS,
    MAX_IMAGE_BLUR,
    MAX_IMAGE_NOISE,
    MAX_IMAGE_SIZE,
    MAX_SUBSTEPS,
)
from radial_ibvs_gym.physics import BACKENDS, RobotConfig
from radial_ibvs_gym.scenarios import Scenario, ScenarioConfig, load_scenario

__all__ = [
    "MAX_GOAL_IMAGE_FRAMES",
    "MAX_HOLD_STEPS",
    "OBS_MODES",
    "REWARD_WEIGHTS",
    "ParkingConfig",
    "UnknownArgumentError",
]

#: the most noisy frames the goal image may average (``goal_image_frames``; ``limits``)
MAX_GOAL_IMAGE_FRAMES = MAX_GOAL_FRAMES


class UnknownArgumentError(TypeError, ValueError):
    """An argument the env does not take, worded as Python's own ``TypeError``.

    Python says ``f() got an unexpected keyword argument 'x'`` for a function's unknown
    argument; libraries that pass optional arguments to ``gym.make`` (TorchRL's ``GymEnv``
    passes ``frameskip``) catch that ``TypeError`` and retry without them. It is also a
    ``ValueError``, as every bad argument of these envs is.
    """


OBS_MODES = ("points", "features")

#: the reward weights among the arguments, in the order of the reward terms
REWARD_WEIGHTS = (
    "w_position",
    "w_heading",
    "w_precision",
    "time_penalty",
    "collision_penalty",
    "lost_penalty",
    "success_bonus",
)


@dataclass(frozen=True)
class ParkingConfig:
    """The arguments of the parking envs, validated (see ``ParkingEnv``'s Arguments table).

    Make one with :meth:`from_kwargs` (the keyword arguments of ``gym.make``); the scenario is
    loaded then, with the keywords that are scenario keys as overrides. Units: seconds,
    metres, degrees where the name says so.

    Raises
    ------
    ValueError
        For a bad value; the message names the argument and the value.
    """

    scenario: Scenario
    task: int | None = None
    physics: Literal["pymunk", "kinematic"] = "pymunk"
    physics_dt: float = 0.01
    obs_mode: Literal["points", "features"] = "points"
    action_type: Literal["twist", "wheels"] = "twist"
    privileged: bool = False
    goal_depths: bool = False
    privileged_map: bool = False
    privileged_goal: Literal["true", "image"] = "true"
    measurement: Literal["ideal", "detected"] = "ideal"
    image_size: int = 256
    beacon_radius: float = 0.08
    image_noise: float = 0.0
    image_blur: float = 0.0
    exposure: float = 1.0
    control_dt: float = 0.1
    success_position_m: float = SUCCESS_TOLERANCES[TASK_TOLERANCE][0]
    success_heading_deg: float = SUCCESS_TOLERANCES[TASK_TOLERANCE][1]
    success_hold_steps: int | None = None
    min_visible: int = 3
    terminate_on_collision: bool = True
    max_landmarks: int | None = None
    slot_order: Literal["fixed", "random"] = "fixed"
    missed_detections: Any = None
    start_reach: float = 1.0
    goal_image_frames: int = 1
    w_position: float = 1.0
    w_heading: float = 0.3
    w_precision: float = 0.0
    time_penalty: float = 0.01
    collision_penalty: float = 1.0
    lost_penalty: float = 1.0
    success_bonus: float = 10.0

    @classmethod
    def argument_names(cls) -> list[str]:
        """Return the env arguments this config holds (``scenario`` included), sorted."""
        return sorted(f.name for f in dataclasses.fields(cls))

    @classmethod
    def from_kwargs(
        cls,
        scenario: str | Path = "paper-sim",
        extra: tuple[str, ...] = (),
        owner: str = "ParkingEnv.__init__",
        **kwargs: Any,
    ) -> ParkingConfig:
        """Validate the env's keyword arguments and load the scenario.

        Parameters
        ----------
        scenario
            A shipped scenario's name or a YAML path.
        extra
            Argument names that the calling env takes itself (listed in the error message).
        owner
            The function that takes these arguments, as an unknown one's error names it.
        **kwargs
            The config's fields, and scenario keys (overrides, e.g. ``depth_scale=1.3``).

        Raises
        ------
        UnknownArgumentError
            For an unknown keyword (with a did-you-mean and the valid names): a ``TypeError``
            worded as Python's, and a ``ValueError``.
        ValueError
            For a bad value.
        """
        own = {f.name for f in dataclasses.fields(cls)} - {"scenario"}
        scenario_keys = sorted(f.name for f in dataclasses.fields(ScenarioConfig))
        unknown = sorted(set(kwargs) - own - set(scenario_keys))
        if unknown:
            arguments = sorted({*cls.argument_names(), *extra, "render_mode"})
            hint = did_you_mean(unknown[0], [*arguments, *scenario_keys])
            raise UnknownArgumentError(
                f"{owner}() got an unexpected keyword argument {unknown[0]!r}{hint}; unknown: "
                f"{short(unknown)}; the env's arguments: {arguments}; scenario keys "
                f"(overrides): {scenario_keys}"
            )
        overrides = {k: v for k, v in kwargs.items() if k not in own}
        fields = {k: v for k, v in kwargs.items() if k in own}
        cls._check_before_loading(fields)
        return cls(scenario=load_scenario(scenario, **overrides), **fields)

    @staticmethod
    def _check_before_loading(fields: Mapping[str, Any]) -> None:
        """Check the values that do not need the scenario (so a typo costs no loading)."""
        checks = {
            "physics": list(BACKENDS),
            "obs_mode": list(OBS_MODES),
            "measurement": ["ideal", "detected"],
            "action_type": ["twist", "wheels"],
        }
        for name, valid in checks.items():
            if name in fields and fields[name] not in valid:
                raise ValueError(f"unknown {name} {fields[name]!r}; valid: {valid}")
        for name in ("control_dt", "physics_dt", "success_position_m", "success_heading_deg"):
            value = fields.get(name, 1.0)
            if not (math.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be finite and positive, got {value!r}")

    def __post_init__(self) -> None:
        for name in (
            "task", "max_landmarks", "min_visible", "goal_image_frames", "success_hold_steps",
        ):  # fmt: skip
            value = getattr(self, name)
            if value is None and name in ("task", "max_landmarks", "success_hold_steps"):
                continue  # None: drawn per episode, no slots, or a park (resolved below)
            if isinstance(value, bool) or not isinstance(value, int):
                raise ValueError(f"{name} must be an integer, got {value!r}")
        self._check_before_loading({f.name: getattr(self, f.name) for f in _CHECKED})
        if self.success_hold_steps is None:  # a park: 1 s held, at this control period
            object.__setattr__(self, "success_hold_steps", park_hold_steps(self.control_dt))
        n = self.scenario.n_landmarks
        if self.task is not None and not (0 <= self.task < self.scenario.n_tasks):
            raise ValueError(f"task must be in 0..{self.scenario.n_tasks - 1}, got {self.task!r}")
        if not (3 <= self.min_visible <= n):
            raise ValueError(f"min_visible must be in 3..{n}, got {self.min_visible!r}")
        if not (1 <= self.hold_steps <= MAX_HOLD_STEPS):
            raise ValueError(
                f"success_hold_steps must be in 1..{MAX_HOLD_STEPS}, got "
                f"{self.success_hold_steps!r} (the default is {PARK_HOLD_S:g} s: "
                f"{PARK_HOLD_S:g} / control_dt steps)"
            )
        if not (1 <= self.goal_image_frames <= MAX_GOAL_IMAGE_FRAMES):
            raise ValueError(
                f"goal_image_frames must be in 1..{MAX_GOAL_IMAGE_FRAMES}, got "
                f"{self.goal_image_frames!r}"
            )
        self._check_image()
        if self.physics == "pymunk":
            substeps = self.control_dt / self.physics_dt
            if substeps > MAX_SUBSTEPS:
                raise ValueError(
                    f"control_dt={self.control_dt!r} s / physics_dt={self.physics_dt!r} s = "
                    f"{substeps:.4g} physics sub-steps per control period exceed MAX_SUBSTEPS = "
                    f"{MAX_SUBSTEPS}"
                )
            if abs(round(substeps) * self.physics_dt - self.control_dt) > 1e-9:
                raise ValueError(
                    f"control_dt={self.control_dt!r} s must be a multiple of "
                    f"physics_dt={self.physics_dt!r} s"
                )
        for name in REWARD_WEIGHTS:
            weight = getattr(self, name)
            if not (math.isfinite(weight) and weight >= 0):
                raise ValueError(f"{name} must be finite and >= 0, got {weight!r}")
        missed = MissedDetections.from_value(self.missed_detections)
        object.__setattr__(self, "missed_detections", missed)
        if missed is not None and self.measurement == "detected":
            raise ValueError("missed_detections is for measurement='ideal' (detected: real misses)")
        if self.measurement == "detected":
            specs = (self.scenario.config.camera, self.scenario.config.goal_camera)
            if any(s is not None and s.imperfection_ranges is not None for s in specs):
                raise ValueError(
                    "measurement='detected' does not take camera imperfection_ranges; give "
                    "fixed imperfections, or use measurement='ideal'"
                )
        if self.privileged_goal not in ("true", "image"):
            raise ValueError(
                f"unknown privileged_goal {self.privileged_goal!r}; valid: ['true', 'image']"
            )
        if self.privileged_goal == "image" and not self.privileged:
            raise ValueError(
                "privileged_goal='image' changes the privileged goal_pose: needs privileged=True"
            )
        if self.slot_order not in ("fixed", "random"):
            raise ValueError(f"unknown slot_order {self.slot_order!r}; valid: ['fixed', 'random']")
        if self.slot_order == "random" and self.max_landmarks is None:
            raise ValueError("slot_order='random' needs max_landmarks (the slots to draw from)")
        _ = self.slots, self.robot  # max_landmarks and the robot checked now
        self.scenario.check_reach(self.start_reach, self.tasks, "start_reach")

    def _check_image(self) -> None:
        """Bound what a rendered frame costs (``measurement="detected"``; ``limits``)."""
        size = self.image_size
        if isinstance(size, bool) or not isinstance(size, int) or not 16 <= size <= MAX_IMAGE_SIZE:
            raise ValueError(f"image_size must be an integer in 16..{MAX_IMAGE_SIZE}, got {size!r}")
        for name, top, unit in (
            ("image_blur", MAX_IMAGE_BLUR, "pixels"),
            ("image_noise", MAX_IMAGE_NOISE, "grey levels"),
        ):
            value = getattr(self, name)
            if (
                isinstance(value, bool)
                or not isinstance(value, int | float)
                or not (math.isfinite(value) and 0 <= value <= top)
            ):
                raise ValueError(f"{name} must be in [0, {top:g}] {unit}, got {value!r}")

    # --- what follows from the arguments -------------------------------------------------------

    @property
    def tasks(self) -> list[int] | None:
        """The tasks episodes are drawn from: ``[task]``, or ``None`` (any)."""
        return None if self.task is None else [self.task]

    @functools.cached_property
    def robot(self) -> RobotConfig:
        """The scenario's robot."""
        return RobotConfig.from_dict(dict(self.scenario.config.robot))

    @functools.cached_property
    def scale(self) -> tuple[float, float]:
        """What an action of 1 means: ``(v, omega)`` in m/s and rad/s, or wheel speeds, rad/s.

        With ``action_type="wheels"`` full scale is the wheel speed of the top linear speed.
        """
        if self.action_type == "twist":
            return (self.robot.max_linear_speed, self.robot.max_angular_speed)
        return (self.robot.max_linear_speed / self.robot.wheel_radius,) * 2

    @functools.cached_property
    def pairs(self) -> tuple[np.ndarray, np.ndarray]:
        """The ``(i, j)`` index arrays of the landmark pairs of ``c_ij``."""
        return pair_indices(self.scenario.n_landmarks)

    @functools.cached_property
    def slots(self) -> Slots | None:
        """The landmark slots (``max_landmarks``), or ``None``: N landmarks are observed."""
        if self.max_landmarks is None:
            return None
        return Slots(self.scenario.n_landmarks, self.max_landmarks)

    @property
    def hold_steps(self) -> int:
        """Steps in a row within the tolerances a success asks (``success_hold_steps``, resolved).

        ``success_hold_steps=None`` (the default) is a park: :data:`~.rules.PARK_HOLD_S` over
        ``control_dt``, 10 steps at 0.1 s.
        """
        assert self.success_hold_steps is not None  # resolved in __post_init__
        return self.success_hold_steps

    @property
    def observed_landmarks(self) -> int:
        """The landmark entries of an observation: the slots, or the scene's landmarks."""
        return self.scenario.n_landmarks if self.slots is None else self.slots.m

    @functools.cached_property
    def success_heading_rad(self) -> float:
        """The heading tolerance of success, radians."""
        return math.radians(self.success_heading_deg)

    @functools.cached_property
    def weights(self) -> dict[str, float]:
        """The reward weights (:data:`REWARD_WEIGHTS`), by name."""
        return {name: getattr(self, name) for name in REWARD_WEIGHTS}

    @property
    def map_obstacles(self) -> int:
        """Rows of the ``obstacles`` map observation: the scenario's most obstacles (>= 1)."""
        config = self.scenario.config
        drawn = config.random_obstacles.count[1] if config.random_obstacles is not None else 0
        return max(1, len(config.obstacles) + drawn)


#: the fields checked before the scenario is loaded
_CHECKED = [
    f
    for f in dataclasses.fields(ParkingConfig)
    if f.name
    in (
        "physics",
        "obs_mode",
        "measurement",
        "action_type",
        "control_dt",
        "physics_dt",
        "success_position_m",
        "success_heading_deg",
    )
]
