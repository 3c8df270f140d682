"""``RadialIBVS/Parking-v0``: park a differential-drive robot seen only through a goal image."""

from __future__ import annotations

import dataclasses
import functools
import inspect
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from radial_ibvs_gym.camera import Imperfections
from radial_ibvs_gym.config import did_you_mean, short
from radial_ibvs_gym.envs import logic
from radial_ibvs_gym.envs.missed import MissedDetections, MissedState
from radial_ibvs_gym.features import c_ij, pair_indices
from radial_ibvs_gym.geometry import world_to_camera, wrap_angle_scalar
from radial_ibvs_gym.physics import BACKENDS, RobotConfig, World, make_world, wheels_to_twist
from radial_ibvs_gym.physics.base import footprint_collides, start_pose_error
from radial_ibvs_gym.scenarios import Episode, Scenario, ScenarioConfig, load_scenario
from radial_ibvs_gym.vision import ImageQuality
from radial_ibvs_gym.vision.pipeline import DetectedPoints

__all__ = ["EpisodeSetup", "ParkingEnv"]

OBS_MODES = ("points", "features")


@dataclass
class EpisodeSetup:
    """What an env keeps of a drawn episode (the scalar and the vector envs alike).

    Attributes
    ----------
    episode
        The drawn episode (room, landmarks, start, goal; the goal's yaw wrapped).
    goal_depths
        ``(N,)`` goal depths ``d*`` given to the policy, metres (times ``depth_scale``).
    landmarks_c
        ``(N,)`` the landmarks on the floor plane as complex numbers ``x + i y``, metres.
    radius_bounds
        Per camera (``"current"``, ``"goal"``): the interval of horizontal distances the mirror
        sees at each landmark's height, ``(lo, hi)`` each ``(N,)``; ``None`` for a camera with
        imperfections (projected exactly instead).
    goal_points, goal_visible
        ``(N, 2)`` the goal image (zeros where hidden) and ``(N,)`` its visibility.
    c_goal
        ``(M,)`` the goal image's ``c*_ij`` (``obs_mode="features"``; else ``None``).
    cameras
        The episode's cameras, ``"current"`` and ``"goal"``: the scenario's, or built with
        the imperfections drawn for this episode.
    imperfections
        The imperfections drawn for this episode (``None``: the scenario draws none).
    map
        The privileged map of the episode (:meth:`ParkingEnv.map_observation`), computed
        once at reset when ``privileged_map=True``; else ``None``.
    missed
        The episode's missed detections (``missed_detections``), or ``None``.
    """

    episode: Episode
    goal_depths: np.ndarray
    landmarks_c: np.ndarray
    radius_bounds: dict[str, tuple[np.ndarray, np.ndarray] | None]
    goal_points: np.ndarray
    goal_visible: np.ndarray
    c_goal: np.ndarray | None = None
    cameras: dict[str, Any] = field(default_factory=dict)
    imperfections: Imperfections | None = None
    map: dict[str, np.ndarray] | None = None
    slot_order: np.ndarray | None = None
    missed: MissedState | None = None


def _check_env_arguments(overrides: dict[str, Any], env: type) -> None:
    """Refuse keywords that are neither env arguments nor scenario keys, with a did-you-mean.

    Checked before the scenario is loaded, so a typo of an env argument (``phisics=``) is
    reported as such, with the env's own arguments listed beside the scenario's keys.
    """
    scenario_keys = sorted(f.name for f in dataclasses.fields(ScenarioConfig))
    unknown = sorted(set(overrides) - set(scenario_keys))
    if not unknown:
        return
    arguments = sorted(
        {
            name
            for cls in env.__mro__
            if "__init__" in vars(cls) and cls.__module__.startswith("radial_ibvs_gym")
            for name, p in inspect.signature(vars(cls)["__init__"]).parameters.items()
            if name != "self" and p.kind is not inspect.Parameter.VAR_KEYWORD
        }
    )
    hint = did_you_mean(unknown[0], [*arguments, *scenario_keys])
    raise ValueError(
        f"unknown argument(s) {short(unknown)}{hint}; the env's arguments: {arguments}; "
        f"scenario keys (overrides): {scenario_keys}"
    )


class ParkingEnv(gym.Env[dict[str, np.ndarray], np.ndarray]):
    """Park a Pioneer-like robot at a goal pose that is known only by its omnidirectional image.

    ## Description
    The robot carries a catadioptric camera (the paper's mirror A by default, non-central). The
    scene's landmarks are seen as normalised radial image points ``x_n`` on the unit circle
    (eq. 9 of Aliakbarpour, Tahri and Araujo, RAS 2014); the goal is given as the image
    ``x_n*`` taken at the goal pose. The task is the paper's parking problem (Section 4).

    ## Action Space
    ``Box(-1, 1, (2,), float32)``:

    | index | meaning | mapped to |
    |---|---|---|
    | 0 | linear speed | ``v = a0 * max_linear_speed`` (m/s) |
    | 1 | angular speed | ``omega = a1 * max_angular_speed`` (rad/s) |

    With ``action_type="wheels"`` the two values are the left and right wheel speeds instead,
    in units of the wheel speed that gives ``max_linear_speed``. Values are clipped to
    ``[-1, 1]``; a NaN or infinite action raises ``ValueError``. The robot's speed and
    acceleration limits then apply (``RobotConfig``).

    ## Observation Space
    A ``Dict`` (``N`` landmarks, ``M = N (N - 1) / 2``):

    | key | space | meaning |
    |---|---|---|
    | ``points`` | ``Box(-1, 1, (2N,))`` | current ``x_n``, flattened ``(x_1, y_1, ...)`` (1) |
    | ``goal_points`` | ``Box(-1, 1, (2N,))`` | goal image ``x_n*``, flattened likewise (1) |
    | ``visible`` | ``Box(0, 1, (N,))`` | 1 where the landmark is visible now |
    | ``c_error`` | ``Box(-2, 2, (M,))`` | ``c*_ij - c_ij`` (2) |
    | ``alpha_m_error`` | ``Box(-pi, pi, (1,))`` | ``alpha_m* - alpha_m``, radians (2) |

    (1) zeros where the landmark is not visible. (2) ``obs_mode="features"`` only; 0 for pairs
    with a hidden point; ``alpha_m`` uses the virtual point of the visible landmarks.
    With ``goal_depths=True``, ``goal_depths`` ``Box(0, 1e3, (N,))`` adds the goal depths ``d*``
    (horizontal distances at the goal, metres, times the scenario's ``depth_scale``): the only
    3D knowledge the paper's IBVS uses. With ``privileged=True`` the true ``robot_pose`` and
    ``goal_pose`` ``(x, y, yaw)`` (metres, radians, world frame) and the current true
    ``depths`` ``(N,)`` (metres) are added: for the pose oracle and the classic IBVS variants,
    never for a vision-based policy. With ``privileged_map=True`` the map is added (for the
    ``planner``): ``room`` ``(2,)``, ``obstacles`` ``(K, 3)`` ``(x, y, radius)``, ``landmarks``
    ``(N, 3)`` and ``landmark_range`` ``(N, 2)``, the horizontal distances at which the nominal
    camera sees each landmark (metres, zero-padded). With ``max_landmarks=M`` every
    per-landmark entry is padded with zeros to ``M`` slots (``c_error`` to the
    ``M (M - 1) / 2`` pairs, each pair at its place among the slots' pairs) and
    ``landmark_mask`` ``Box(0, 1, (M,))`` marks the scene's landmarks: one observation space
    for every scene with at most ``M`` landmarks, so one learned model runs in all of them.
    Landmark ``n`` fills slot ``n``; with ``slot_order="random"`` each episode puts its ``N``
    landmarks in ``N`` of the ``M`` slots drawn at random (the last draw of ``reset``, from
    the env's generator), so that a model trained in scenes of ``N`` landmarks has learned
    every slot and every pair, not only the first ``N`` (the map's rows stay in the scene's
    order).

    ## Detected points
    With ``measurement="detected"`` the points come from images, as in the paper's lab
    (Section 4.2): each frame is rendered (:mod:`radial_ibvs_gym.vision`), the beacons are
    detected with OpenCV, normalised with the principal point and ``rho_f`` of the mirror border
    fitted on the goal image (eq. 7), and matched with the landmarks by a tracker
    (:class:`~radial_ibvs_gym.vision.track.BeaconTracker`; method in ``docs/pixels.md``).
    ``info["detection"]`` holds ``status`` (``"ok"`` or ``"no_beacons"``), ``n_detected``,
    ``n_tracked``, ``principal_point_px``, ``rho_f`` and the ``rejected`` blob counts. A bad
    frame never raises: a landmark without a blob keeps its last position for 3 frames, then it
    is hidden; with fewer than ``min_visible`` left the episode ends "lost" as in ideal mode. A
    goal image without a mirror border raises ``ValueError`` at reset (no calibration); one with
    fewer than ``min_visible`` detected beacons is drawn again (at most 10 times).

    ## Rewards
    ``r = progress + heading + precision + time + collision + lost + success`` (named in
    ``info["reward_terms"]``): ``progress = w_position (e_p(t-1) - e_p(t))`` (position error in
    metres), ``heading = w_heading (e_h(t-1) - e_h(t))`` (radians), ``precision =
    w_precision (phi(t) - phi(t-1))`` with the potential ``phi = -ln(e_p + 0.01) - 0.5
    ln(e_h + 0.02)`` (potential-based shaping: it sharpens the reward near the goal, where
    learned policies need centimetre precision, without changing the optimal policy; off by
    default), ``time = -time_penalty``, ``collision = -collision_penalty`` on a collision,
    ``lost = -lost_penalty`` when too few landmarks remain visible, ``success = success_bonus``
    on success.

    ## Starting State
    Drawn from the scenario (``paper-sim``: start (3, 3) m heading 0, goal (7, 7) m with the
    task's yaw). ``reset(options={"start": pose, "goal": pose, "task": k})`` fixes them.
    ``start_reach`` (constructor or attribute, in ``(0, 1]``) draws starts near the goal, for
    a reverse curriculum: within ``start_reach`` times the scenario's start-goal distances and
    ``start_reach * pi`` radians of the goal's heading (scenarios that start ``anywhere``).

    ## Episode End
    Termination: success (position error <= ``success_position_m`` and heading error <=
    ``success_heading_deg``), a collision (if ``terminate_on_collision``), or fewer than
    ``min_visible`` visible landmarks (``info["lost"]`` is then ``True``). Truncation:
    ``max_episode_steps`` of the registration (600 steps of ``control_dt = 0.1`` s).

    ## Arguments
    | argument | default | meaning |
    |---|---|---|
    | ``scenario`` | ``"paper-sim"`` | shipped name or YAML path |
    | ``task`` | ``None`` | task index; ``None`` draws one per episode |
    | ``physics`` | ``"pymunk"`` | ``"pymunk"`` (contacts) or ``"kinematic"`` (exact unicycle) |
    | ``physics_dt`` | ``0.01`` | pymunk sub-step, seconds (``control_dt`` is a multiple) |
    | ``obs_mode`` | ``"points"`` | ``"points"`` or ``"features"`` |
    | ``action_type`` | ``"twist"`` | ``"twist"`` ``(v, omega)`` or ``"wheels"`` (left, right) |
    | ``goal_depths`` | ``False`` | add the goal depths ``d*`` to the observation (IBVS) |
    | ``privileged`` | ``False`` | add the true poses and depths to the observation |
    | ``privileged_map`` | ``False`` | add the map (room, obstacles, landmarks; see below) |
    | ``measurement`` | ``"ideal"`` | ``"ideal"`` projection, or ``"detected"`` (see below) |
    | ``image_size`` / ``beacon_radius`` | ``256`` / ``0.08`` | detected mode: pixels / metres |
    | ``image_noise`` / ``image_blur`` / ``exposure`` | ``0`` / ``0`` / ``1`` | detected mode |
    | ``control_dt`` | ``0.1`` | control period, seconds |
    | ``success_position_m`` / ``success_heading_deg`` | ``0.02`` / ``2.0`` | success tolerances |
    | ``min_visible`` | ``3`` | fewer visible landmarks terminate the episode |
    | ``terminate_on_collision`` | ``True`` | |
    | ``max_landmarks`` | ``None`` | landmark slots: pad to this many, add ``landmark_mask`` |
    | ``slot_order`` | ``"fixed"`` | ``"random"``: the landmarks' slots drawn per episode |
    | ``missed_detections`` | ``None`` | ``{"rate": p, "steps": [lo, hi]}``: missed landmarks |
    | ``start_reach`` | ``1.0`` | in (0, 1]: starts near the goal, for a curriculum (below) |
    | ``**scenario_overrides`` | | scenario keys, e.g. ``depth_scale=1.3`` |

    ```python
    import gymnasium as gym
    import radial_ibvs_gym  # registers the environments

    env = gym.make("RadialIBVS/Parking-v0", scenario="paper-sim", task=1)
    obs, info = env.reset(seed=0)
    ```

    ## Version History
    - v0: initial version.
    """

    metadata: dict[str, Any] = {"render_modes": ["human", "rgb_array"], "render_fps": 10}  # noqa: RUF012

    def __init__(
        self,
        scenario: str | Path = "paper-sim",
        task: int | None = None,
        physics: Literal["pymunk", "kinematic"] = "pymunk",
        physics_dt: float = 0.01,
        obs_mode: Literal["points", "features"] = "points",
        action_type: Literal["twist", "wheels"] = "twist",
        privileged: bool = False,
        goal_depths: bool = False,
        privileged_map: bool = False,
        measurement: Literal["ideal", "detected"] = "ideal",
        image_size: int = 256,
        beacon_radius: float = 0.08,
        image_noise: float = 0.0,
        image_blur: float = 0.0,
        exposure: float = 1.0,
        control_dt: float = 0.1,
        success_position_m: float = 0.02,
        success_heading_deg: float = 2.0,
        min_visible: int = 3,
        terminate_on_collision: bool = True,
        max_landmarks: int | None = None,
        slot_order: Literal["fixed", "random"] = "fixed",
        missed_detections: Mapping[str, Any] | MissedDetections | None = None,
        start_reach: float = 1.0,
        w_position: float = 1.0,
        w_heading: float = 0.3,
        w_precision: float = 0.0,
        time_penalty: float = 0.01,
        collision_penalty: float = 1.0,
        lost_penalty: float = 1.0,
        success_bonus: float = 10.0,
        render_mode: str | None = None,
        **scenario_overrides: Any,
    ) -> None:
        if physics not in BACKENDS:
            raise ValueError(f"unknown physics {physics!r}; valid: {list(BACKENDS)}")
        if obs_mode not in OBS_MODES:
            raise ValueError(f"unknown obs_mode {obs_mode!r}; valid: {list(OBS_MODES)}")
        if measurement not in ("ideal", "detected"):
            raise ValueError(f"unknown measurement {measurement!r}; valid: ['ideal', 'detected']")
        if action_type not in ("twist", "wheels"):
            raise ValueError(f"unknown action_type {action_type!r}; valid: ['twist', 'wheels']")
        for name, value in (
            ("control_dt", control_dt),
            ("physics_dt", physics_dt),
            ("success_position_m", success_position_m),
            ("success_heading_deg", success_heading_deg),
        ):
            if not (math.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be finite and positive, got {value!r}")
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(
                f"render_mode {render_mode!r} is not supported; valid: "
                f"{self.metadata['render_modes']}"
            )
        _check_env_arguments(scenario_overrides, type(self))
        self.scenario: Scenario = load_scenario(scenario, **scenario_overrides)
        if task is not None and not (0 <= task < self.scenario.n_tasks):
            raise ValueError(f"task must be in 0..{self.scenario.n_tasks - 1}, got {task!r}")
        n = self.scenario.n_landmarks
        if not (3 <= min_visible <= n):
            raise ValueError(f"min_visible must be in 3..{n}, got {min_visible!r}")
        self.task = task
        self.start_reach = start_reach
        self.physics = physics
        self.obs_mode = obs_mode
        self.action_type = action_type
        self.privileged = bool(privileged)
        self.privileged_map = bool(privileged_map)
        self.goal_depths_in_obs = bool(goal_depths)
        self.control_dt = float(control_dt)
        self.physics_dt = float(physics_dt)
        if (
            physics == "pymunk"
            and abs(round(control_dt / physics_dt) * physics_dt - control_dt) > 1e-9
        ):
            raise ValueError(
                f"control_dt={control_dt!r} s must be a multiple of physics_dt={physics_dt!r} s"
            )
        self.success_position_m = float(success_position_m)
        self.success_heading_rad = math.radians(success_heading_deg)
        self.min_visible = int(min_visible)
        self.terminate_on_collision = bool(terminate_on_collision)
        self.weights = {
            "w_position": w_position,
            "w_heading": w_heading,
            "w_precision": w_precision,
            "time_penalty": time_penalty,
            "collision_penalty": collision_penalty,
            "lost_penalty": lost_penalty,
            "success_bonus": success_bonus,
        }
        for name, weight in self.weights.items():
            if not (math.isfinite(weight) and weight >= 0):
                raise ValueError(f"{name} must be finite and >= 0, got {weight!r}")
        self.render_mode = render_mode
        self.measurement = measurement
        self.missed_detections = MissedDetections.from_value(missed_detections)
        if self.missed_detections is not None and measurement == "detected":
            raise ValueError("missed_detections is for measurement='ideal' (detected: real misses)")
        self._detector: DetectedPoints | None = None
        if measurement == "detected":
            specs = (self.scenario.config.camera, self.scenario.config.goal_camera)
            if any(s is not None and s.imperfection_ranges is not None for s in specs):
                raise ValueError(
                    "measurement='detected' does not take camera imperfection_ranges; give "
                    "fixed imperfections, or use measurement='ideal'"
                )
            self._detector = DetectedPoints(
                self.scenario.camera,
                self.scenario.goal_camera,
                self.scenario.config.camera_height,
                image_size=image_size,
                beacon_radius=beacon_radius,
                quality=ImageQuality(image_noise, image_blur, exposure),
            )
        self.robot = RobotConfig.from_dict(dict(self.scenario.config.robot))
        if action_type == "twist":
            self._scale = (self.robot.max_linear_speed, self.robot.max_angular_speed)
        else:  # wheel angular speeds, full scale = the wheel speed of the top linear speed
            self._scale = (self.robot.max_linear_speed / self.robot.wheel_radius,) * 2
        self._pairs = pair_indices(n)
        #: fixed landmark slots (``max_landmarks``), or None: the observation has N landmarks
        self.slots = None if max_landmarks is None else logic.Slots(n, max_landmarks)
        if slot_order not in ("fixed", "random"):
            raise ValueError(f"unknown slot_order {slot_order!r}; valid: ['fixed', 'random']")
        if slot_order == "random" and self.slots is None:
            raise ValueError("slot_order='random' needs max_landmarks (the slots to draw from)")
        self.slot_order = slot_order
        k = n if max_landmarks is None else int(max_landmarks)  # landmark entries observed

        self.action_space = spaces.Box(-1.0, 1.0, (2,), np.float32)
        obs_spaces: dict[str, spaces.Space[Any]] = {
            "points": spaces.Box(-1.0, 1.0, (2 * k,), np.float32),
            "goal_points": spaces.Box(-1.0, 1.0, (2 * k,), np.float32),
            "visible": spaces.Box(0.0, 1.0, (k,), np.float32),
        }
        if obs_mode == "features":
            m = k * (k - 1) // 2
            obs_spaces["c_error"] = spaces.Box(-2.0, 2.0, (m,), np.float32)
            obs_spaces["alpha_m_error"] = spaces.Box(-np.pi, np.pi, (1,), np.float32)
        depth_space = spaces.Box(0.0, 1e3, (k,), np.float32)  # metres
        if goal_depths:
            obs_spaces["goal_depths"] = depth_space
        if privileged:
            bound = np.array([1e3, 1e3, np.pi])  # metres, metres, radians (yaw wrapped)
            pose_space = spaces.Box(-bound, bound, (3,), np.float64)
            obs_spaces["robot_pose"] = pose_space
            obs_spaces["goal_pose"] = pose_space
            obs_spaces["depths"] = depth_space
        if self.privileged_map:
            obs_spaces["room"] = spaces.Box(0.0, 1e3, (2,), np.float64)
            obs_spaces["obstacles"] = spaces.Box(-1e3, 1e3, (self.map_obstacles, 3), np.float64)
            obs_spaces["landmarks"] = spaces.Box(-1e3, 1e3, (k, 3), np.float64)
            obs_spaces["landmark_range"] = spaces.Box(0.0, 1e3, (k, 2), np.float64)
        if self.slots is not None:
            obs_spaces["landmark_mask"] = spaces.Box(0.0, 1.0, (k,), np.float32)
        self.observation_space = spaces.Dict(obs_spaces)  # type: ignore[assignment]

        self._renderer: Any = None
        self.world: World | None = None
        self.episode: Episode | None = None
        self._setup: EpisodeSetup | None = None
        self._bounds_cache: dict[str, tuple[np.ndarray, np.ndarray]] = {}
        self._prev_errors: tuple[Any, Any] = (0.0, 0.0)

    # --- step ----------------------------------------------------------------------------------
    def step(
        self, action: np.ndarray
    ) -> tuple[dict[str, np.ndarray], float, bool, bool, dict[str, Any]]:
        """Apply one action for ``control_dt`` seconds (see the class docstring)."""
        if self.world is None or self._setup is None:
            raise RuntimeError("call reset() before step()")
        a = np.asarray(action, dtype=np.float64).reshape(-1)
        if a.shape != (2,):
            raise ValueError(f"action must be {logic.ACTION_RULE}, got {action!r}")
        a0, a1 = a.tolist()
        if not (math.isfinite(a0) and math.isfinite(a1)):
            raise ValueError(f"action must be {logic.ACTION_RULE}, got {action!r}")
        s0, s1 = self._scale
        command = (min(max(a0, -1.0), 1.0) * s0, min(max(a1, -1.0), 1.0) * s1)
        if self.action_type == "wheels":
            command = tuple(wheels_to_twist(command, self.robot).tolist())
        result = self.world.step(command, self.control_dt)
        self._observe(result.pose)
        now = logic.pose_errors(result.pose.tolist(), self._goal)
        success, lost, terminated = logic.episode_end(
            *now,
            self._n_visible,
            result.collision,
            success_position_m=self.success_position_m,
            success_heading_rad=self.success_heading_rad,
            min_visible=self.min_visible,
            terminate_on_collision=self.terminate_on_collision,
        )
        terms = logic.reward_terms(
            self._prev_errors, now, result.collision, lost, success, self.weights
        )
        self._prev_errors = now
        info = self._info(result.pose, now, bool(success), result.collision, bool(lost))
        info["reward_terms"] = terms
        if self.render_mode is not None:
            self._trail.append(result.pose[:2].copy())
        if self.render_mode == "human":
            self.render()
        return self._obs(), float(sum(terms.values())), bool(terminated), False, info

    # --- reset ---------------------------------------------------------------------------------
    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
        """Draw an episode from the scenario; ``options`` may fix ``start``, ``goal``, ``task``."""
        super().reset(seed=seed)
        options = dict(options or {})
        unknown = sorted(set(options) - {"start", "goal", "task"})
        if unknown:
            raise ValueError(f"unknown reset option(s) {unknown}; valid: ['goal', 'start', 'task']")
        setup = self.setup_episode(self.np_random, options.get("task", self.task), options)
        episode = setup.episode
        self._setup, self.episode = setup, episode
        self._goal = tuple(episode.goal.tolist())
        room = (float(episode.room[0]), float(episode.room[1]))
        extra = {"physics_dt": self.physics_dt} if self.physics == "pymunk" else {}
        obstacles = tuple(tuple(o) for o in episode.obstacles.tolist())
        self.world = make_world(self.physics, self.robot, room, obstacles=obstacles, **extra)
        self.world.reset(episode.start)
        if self.obs_mode == "features":
            self._weights_cache: dict[bytes, np.ndarray | None] = {}
        if self._detector is not None:
            self._points, self._visible = self._detector.initial()
            self._n_visible = int(np.count_nonzero(self._visible))
        else:
            self._observe(episode.start)
        self._prev_errors = logic.pose_errors(episode.start.tolist(), self._goal)
        self._renderer = None
        self._trail: list[np.ndarray] = [episode.start[:2].copy()]
        if self.render_mode == "human":
            self.render()
        info = self._info(episode.start, self._prev_errors, False, False)
        return self._obs(), info

    @property
    def start_reach(self) -> float:
        """The fraction of the start distribution drawn from, in ``(0, 1]`` (a curriculum).

        At ``1`` the scenario draws starts as it says. Below, each start lies within
        ``start_reach`` times the scenario's start-goal distance bounds of its goal, with a
        heading within ``start_reach * pi`` radians of the goal's
        (:meth:`radial_ibvs_gym.scenarios.Scenario.sample`). Setting it takes effect at the
        next reset: a reverse curriculum raises it from near 0 to 1 over training. Only for
        scenarios whose starts are ``anywhere`` (``random``, ``random-obstacles``).
        """
        return self._start_reach

    @start_reach.setter
    def start_reach(self, value: float) -> None:
        tasks = None if self.task is None else [self.task]
        self._start_reach = self.scenario.check_reach(value, tasks, "start_reach")

    def setup_episode(
        self, rng: np.random.Generator, task: int | None, options: dict[str, Any]
    ) -> EpisodeSetup:
        """Draw an episode with ``rng`` and take its goal image (the vector env uses it too).

        Parameters
        ----------
        rng
            The env's generator.
        task
            Task index, or ``None`` to draw one.
        options
            Reset options: ``start`` and ``goal`` poses fix those of the episode.

        Raises
        ------
        ValueError
            For a bad option, or a goal image with fewer than ``min_visible`` landmarks
            (detected points: in 10 draws).
        """
        # detected points: a goal image can show fewer beacons than the scenario guaranteed
        # (too small, cut by the rim); draw again, a bounded number of times
        attempts = 10 if self._detector is not None and "goal" not in options else 1
        for attempt in range(attempts):
            episode = self._draw_episode(rng, task, options)
            cameras, drawn = self._episode_cameras(rng)
            landmarks = episode.landmarks
            heights = landmarks[:, 2] - self.scenario.config.camera_height
            bounds: dict[str, tuple[np.ndarray, np.ndarray] | None] = {}
            for which, camera in cameras.items():
                bounds[which] = self._radius_bounds(which, camera, heights)
            setup = EpisodeSetup(
                episode=episode,
                goal_depths=self.scenario.goal_depths(episode),
                landmarks_c=landmarks[:, 0] + 1j * landmarks[:, 1],
                radius_bounds=bounds,
                goal_points=np.zeros((len(landmarks), 2)),
                goal_visible=np.zeros(len(landmarks), dtype=bool),
                cameras=cameras,
                imperfections=drawn,
            )
            if self._detector is not None:
                setup.goal_points, setup.goal_visible = self._detector.reset(
                    episode.room, episode.landmarks, episode.start, episode.goal, rng
                )
            else:
                setup.goal_points, setup.goal_visible = self.image(setup, episode.goal, "goal", rng)
            if setup.goal_visible.sum() >= self.min_visible:
                break
            if attempt == attempts - 1:
                seen = "detected" if self._detector is not None else "visible"
                raise ValueError(
                    f"only {int(setup.goal_visible.sum())} landmarks are {seen} at the goal "
                    f"{episode.goal.tolist()}; at least {self.min_visible} are needed"
                    + (f" (in {attempts} draws)" if attempts > 1 else "")
                )
        if self.obs_mode == "features":
            setup.c_goal = c_ij(logic.unit_or_dummy(setup.goal_points, setup.goal_visible))
        if self.privileged_map:  # fixed for the episode: computed once, copied at each step
            setup.map = self.map_observation(setup.episode)
        if self.missed_detections is not None:
            setup.missed = self.missed_detections.start(rng, len(setup.episode.landmarks))
        if self.slot_order == "random":  # the last draw: the episode is the same as fixed's
            assert self.slots is not None
            setup.slot_order = self.slots.draw_order(rng)
        return setup

    def _episode_cameras(
        self, rng: np.random.Generator
    ) -> tuple[dict[str, Any], Imperfections | None]:
        """Return the episode's cameras, imperfections drawn where the scenario gives ranges.

        The goal image is taken by the same real camera (the same calibration errors; its
        own pixel noise), unless the scenario names a goal camera of its own.
        """
        config = self.scenario.config
        cameras = {"current": self.scenario.camera, "goal": self.scenario.goal_camera}
        ranges = config.camera.imperfection_ranges
        drawn = None
        if ranges is not None:
            drawn = ranges.draw(rng, config.camera.imperfections)
            cameras["current"] = config.camera.build(drawn)
            if config.goal_camera is None:
                cameras["goal"] = cameras["current"]
        goal_spec = config.goal_camera
        if goal_spec is not None and goal_spec.imperfection_ranges is not None:
            goal_drawn = goal_spec.imperfection_ranges.draw(rng, goal_spec.imperfections)
            cameras["goal"] = goal_spec.build(goal_drawn)
        return cameras, drawn

    def _radius_bounds(
        self, which: str, camera: Any, heights: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray] | None:
        """Return the camera's visible distance interval per landmark height (None: imperfect).

        Cached per camera for scenarios with fixed landmarks (the same heights every episode).
        """
        if camera.imperfections.any:
            return None
        if self.scenario.config.random_landmarks is not None:
            return camera.visible_radius_bounds(heights)
        if which not in self._bounds_cache:
            self._bounds_cache[which] = camera.visible_radius_bounds(heights)
        return self._bounds_cache[which]

    def _draw_episode(
        self, rng: np.random.Generator, task: int | None, options: dict[str, Any]
    ) -> Episode:
        """Draw an episode from the scenario, with the start and goal ``options`` applied."""
        episode = self.scenario.sample(rng, task=task, reach=self._start_reach)
        for key in ("start", "goal"):
            if key in options:
                pose = np.asarray(options[key], dtype=np.float64)
                if pose.shape != (3,) or not np.isfinite(pose).all():
                    raise ValueError(f"options[{key!r}] must be (x, y, yaw), got {options[key]!r}")
                # the same check in every backend, before any physics sees the pose
                if footprint_collides(pose, self.robot, episode.room, episode.obstacles):
                    raise ValueError(f"options[{key!r}]: {start_pose_error(pose, key)}")
                episode = (
                    episode._replace(start=pose) if key == "start" else episode._replace(goal=pose)
                )
        goal = episode.goal.astype(np.float64).copy()
        goal[2] = wrap_angle_scalar(float(goal[2]))
        return episode._replace(goal=goal)

    # --- rendering -----------------------------------------------------------------------------
    def render(self) -> np.ndarray | None:
        """Render the room from above beside the omnidirectional image.

        Returns
        -------
        numpy.ndarray or None
            ``(H, W, 3)`` uint8 RGB for ``render_mode="rgb_array"``; ``None`` for ``"human"``
            (shown in a matplotlib window) or when no render mode was set.
        """
        if self.render_mode is None:
            gym.logger.warn("render() called without a render_mode; pass render_mode to make()")
            return None
        if self.world is None or self.episode is None:
            raise RuntimeError("call reset() before render()")
        if self._renderer is None:
            from radial_ibvs_gym.envs.viewer import ParkingRenderer

            size = (self.robot.length, self.robot.width)
            self._renderer = ParkingRenderer(self.scenario, self.episode, size)
        frame: np.ndarray = self._renderer.frame(self.world.pose, self._trail)
        if self.render_mode == "rgb_array":
            return frame
        import matplotlib.pyplot as plt

        if not hasattr(self, "_window"):
            self._window = plt.figure("RadialIBVS")
            self._window_image = self._window.add_subplot().imshow(frame)
            self._window.axes[0].set_axis_off()
        else:
            self._window_image.set_data(frame)
        plt.pause(1.0 / self.metadata["render_fps"])
        return None

    def close(self) -> None:
        """Release the rendering resources."""
        self._renderer = None
        if hasattr(self, "_window"):
            import matplotlib.pyplot as plt

            plt.close(self._window)
            del self._window

    # --- helpers -------------------------------------------------------------------------------
    def _to_camera(self, pose: np.ndarray) -> np.ndarray:
        assert self.episode is not None
        h = self.scenario.config.camera_height
        return world_to_camera(self.episode.landmarks, pose, h, validate=False)

    def image(
        self, setup: EpisodeSetup, pose: np.ndarray, which: str, rng: np.random.Generator
    ) -> tuple[np.ndarray, np.ndarray]:
        """Normalised image points ``(N, 2)`` (zeros where hidden) and visibility ``(N,)``.

        An ideal camera gives eq. (9) exactly (:func:`~radial_ibvs_gym.envs.logic.radial_image`);
        a camera with imperfections is simulated as the paper's set-up measures
        (:func:`~radial_ibvs_gym.envs.logic.camera_image`, pixel noise from ``rng``).

        Parameters
        ----------
        setup
            The episode.
        pose
            ``(3,)`` robot pose, metres and radians.
        which
            ``"current"`` (the scenario's camera) or ``"goal"`` (its goal camera).
        rng
            The env's generator (pixel noise).
        """
        bounds = setup.radius_bounds[which]
        if bounds is not None:
            return logic.radial_image(setup.landmarks_c, bounds[0], bounds[1], pose)
        camera = setup.cameras[which]
        h = self.scenario.config.camera_height
        p_cam = world_to_camera(setup.episode.landmarks, pose, h, validate=False)
        return logic.camera_image(camera, p_cam, rng)

    def _observe(self, pose: np.ndarray) -> None:
        assert self._setup is not None
        if self._detector is not None:
            self._points, self._visible = self._detector.observe(pose, self.np_random)
        else:
            self._points, self._visible = self.image(self._setup, pose, "current", self.np_random)
            if self._setup.missed is not None:
                self._points, self._visible = self._setup.missed.apply(self._points, self._visible)
        self._n_visible = int(np.count_nonzero(self._visible))

    def _feature_errors(self) -> tuple[np.ndarray, np.ndarray]:
        assert self._setup is not None and self._setup.c_goal is not None
        both = self._visible & self._setup.goal_visible
        key = both.tobytes()
        if key not in self._weights_cache:
            self._weights_cache[key] = logic.goal_weights(self._setup.goal_points, both)
        a = self._weights_cache[key]
        return logic.feature_errors(
            self._points,
            both,
            self._setup.c_goal,
            self._pairs,
            np.zeros(len(both)) if a is None else a,
            np.bool_(a is not None),
        )

    @property
    def map_obstacles(self) -> int:
        """Rows of the ``obstacles`` map observation: the scenario's most obstacles (>= 1)."""
        config = self.scenario.config
        drawn = config.random_obstacles.count[1] if config.random_obstacles is not None else 0
        return max(1, len(config.obstacles) + drawn)

    def map_observation(self, episode: Episode) -> dict[str, np.ndarray]:
        """Return the privileged map of an episode (metres, world frame, zero-padded).

        ``room`` ``(2,)`` width and depth; ``obstacles`` ``(K, 3)`` rows ``(x, y, radius)``
        (radius 0: none); ``landmarks`` ``(L, 3)`` their positions; ``landmark_range``
        ``(L, 2)`` the interval of horizontal distances at which the nominal camera sees each
        landmark (``(0, 0)``: a padded slot; 1000 stands for no upper bound).
        """
        obstacles = np.zeros((self.map_obstacles, 3))
        given = np.asarray(episode.obstacles, dtype=np.float64).reshape(-1, 3)
        obstacles[: len(given)] = given
        k = len(episode.landmarks) if self.slots is None else self.slots.m
        landmarks = np.asarray(episode.landmarks, dtype=np.float64)
        padded = np.zeros((k, 3))
        padded[: len(landmarks)] = landmarks
        ranges = np.zeros((k, 2))
        heights = landmarks[:, 2] - self.scenario.config.camera_height
        bounds = self._nominal_camera.visible_radius_bounds(heights)
        if bounds is not None:  # an on-axis convex mirror (every shipped camera)
            ranges[: len(landmarks), 0] = bounds[0]
            ranges[: len(landmarks), 1] = np.minimum(bounds[1], 1e3)
        else:
            ranges[: len(landmarks), 1] = 1e3
        return {
            "room": np.asarray(episode.room, dtype=np.float64).copy(),
            "obstacles": obstacles,
            "landmarks": padded,
            "landmark_range": ranges,
        }

    @functools.cached_property
    def _nominal_camera(self) -> Any:
        """The scenario's camera without its imperfections: what the map's owner knows."""
        return self.scenario.config.camera.build(Imperfections())

    def _obs(self) -> dict[str, np.ndarray]:
        assert self._setup is not None
        obs = self._image_obs()
        if self._setup.map is not None:
            obs.update({key: value.copy() for key, value in self._setup.map.items()})
        return obs

    def _image_obs(self) -> dict[str, np.ndarray]:
        assert self._setup is not None
        features = None
        if self.obs_mode == "features":
            c_err, a_err = self._feature_errors()
            features = {"c_error": c_err, "alpha_m_error": a_err}
        pose = self.world.pose if self.privileged and self.world is not None else None
        return logic.observation(
            self._points.reshape(-1),
            self._setup.goal_points.reshape(-1),
            self._visible,
            features=features,
            goal_depths=self._setup.goal_depths if self.goal_depths_in_obs else None,
            robot_pose=pose,
            goal_pose=self._setup.episode.goal if self.privileged else None,
            landmarks=self._setup.landmarks_c if self.privileged else None,
            slots=self.slots,
            slot_order=self._setup.slot_order,
        )

    def _info(
        self,
        pose: np.ndarray,
        errors: tuple[Any, Any],
        success: bool,
        collision: bool,
        lost: bool = False,
    ) -> dict[str, Any]:
        assert self._setup is not None
        return {
            "robot_pose": np.asarray(pose, dtype=np.float64).copy(),
            "goal_pose": self._setup.episode.goal.copy(),
            "position_error_m": float(errors[0]),
            "heading_error_deg": math.degrees(float(errors[1])),
            "is_success": bool(success),
            "collision": bool(collision),
            "lost": bool(lost),
            "n_visible": self._n_visible,
            "task": self._setup.episode.task,
            "goal_depths": self._setup.goal_depths.copy(),
            **({"detection": self._detector.info()} if self._detector is not None else {}),
            **(
                {"camera_imperfections": logic.imperfections_info(self._setup.imperfections)}
                if self._setup.imperfections is not None
                else {}
            ),
        }
