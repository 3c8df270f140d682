"""``RadialIBVS/Parking-v0``: park a differential-drive robot seen only through a goal image.

The env's jobs live in their own modules: its arguments in :mod:`~radial_ibvs_gym.envs.config`,
drawing an episode and its goal image in :mod:`~radial_ibvs_gym.envs.episodes`, what the robot
sees in :mod:`~radial_ibvs_gym.envs.observation`, the task's rules (errors, reward, episode end,
``info``) in :mod:`~radial_ibvs_gym.envs.rules`. This module steps, resets and renders.
Its length (about 540 lines) is mostly the class docstring (and the read-only views a recorder
uses: the episode, the image points, the detector's frames): Gymnasium's layout of an env's
documentation (spaces, rewards, episode end, the arguments' table), which the site renders.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np

from radial_ibvs_gym.envs import observation as seen
from radial_ibvs_gym.envs import rules
from radial_ibvs_gym.envs.config import ParkingConfig
from radial_ibvs_gym.envs.detectors import make_detector
from radial_ibvs_gym.envs.episodes import EpisodeSetup, EpisodeSource
from radial_ibvs_gym.envs.feature_errors import FeatureErrors
from radial_ibvs_gym.envs.slots import Slots
from radial_ibvs_gym.physics import RobotConfig, World, make_world, wheels_to_twist
from radial_ibvs_gym.scenarios import Episode, Scenario
from radial_ibvs_gym.vision.pipeline import DetectedPoints

__all__ = ["EpisodeSetup", "ParkingEnv"]

#: the one row of a scalar env's feature errors
_ROW = np.zeros(1, dtype=np.intp)


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
    Options add entries:

    | argument | adds | for |
    |---|---|---|
    | ``goal_depths=True`` | ``goal_depths`` ``Box(0, 1e3, (N,))`` | the paper's IBVS (3) |
    | ``privileged=True`` | ``robot_pose``, ``goal_pose``, ``depths`` | oracles (4) |
    | ``privileged_map=True`` | ``room``, ``obstacles``, ``landmarks``, ``landmark_range`` | (5) |
    | ``max_landmarks=M`` | ``landmark_mask`` ``Box(0, 1, (M,))`` | mixed scenes (6) |

    (3) the goal depths ``d*``: horizontal distances at the goal (metres, times the scenario's
    ``depth_scale``), the only 3D knowledge the paper's IBVS uses. (4) the true poses ``(3,)``
    ``(x, y, yaw)`` (metres, radians, world frame) and depths ``(N,)`` (metres), never for a
    vision-based policy. (5) the map, for the ``planner``: ``room`` ``(2,)``, ``obstacles``
    ``(K, 3)`` ``(x, y, radius)``, ``landmarks`` ``(N, 3)``, ``landmark_range`` ``(N, 2)`` (the
    distances at which the nominal camera sees each landmark, metres, zero-padded). (6) every
    per-landmark entry padded with zeros to ``M`` slots (``c_error`` to the ``M (M - 1) / 2``
    pairs): one observation space for every scene of at most ``M`` landmarks; with
    ``slot_order="random"`` each episode puts its ``N`` landmarks in ``N`` of the ``M`` slots
    drawn at random (the last draw of ``reset``), so that a model trained in scenes of ``N``
    landmarks learns every slot and pair.

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
    ``r = progress + heading + precision + time + collision + lost + success`` (each in
    ``info["reward_<term>"]``, zeros after ``reset``): ``progress = w_position (e_p(t-1) -
    e_p(t))`` (position error in metres), ``heading = w_heading (e_h(t-1) - e_h(t))``
    (radians), ``precision = w_precision (phi(t) - phi(t-1))`` with the potential
    ``phi = -ln(e_p + 0.01) - 0.5 ln(e_h + 0.02)`` (potential-based shaping: it sharpens the
    reward near the goal, where learned policies need centimetre precision, without changing
    the optimal policy; off by default), ``time = -time_penalty``, ``collision =
    -collision_penalty`` on a collision, ``lost = -lost_penalty`` when too few landmarks remain
    visible, ``success = success_bonus`` on success.

    ## Starting State
    Drawn from the scenario (``paper-sim``: start (3, 3) m heading 0, goal (7, 7) m with the
    task's yaw). ``reset(options={"start": pose, "goal": pose, "task": k})`` fixes them.
    ``start_reach`` (constructor or attribute, in ``(0, 1]``) draws starts near the goal, for
    a reverse curriculum: within ``start_reach`` times the scenario's start-goal distances and
    ``start_reach * pi`` radians of the goal's heading (scenarios that start ``anywhere``).

    ## Episode End
    Termination: success, a park (position error <= ``success_position_m`` and heading error
    <= ``success_heading_deg`` held for ``success_hold_steps`` steps in a row: 1 s, 10 steps at
    the default ``control_dt``; ``info["reached"]`` marks the first step of a run within the
    tolerances, and ``success_hold_steps=1`` is the older rule, where a pass counts), a
    collision (if ``terminate_on_collision``), or fewer than
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
    | ``privileged_goal`` | ``"true"`` | ``"image"``: ``goal_pose`` is the goal image's pose |
    | ``measurement`` | ``"ideal"`` | ``"ideal"`` projection, or ``"detected"`` (see below) |
    | ``image_size`` / ``beacon_radius`` | ``256`` / ``0.08`` | detected mode: pixels / metres |
    | ``image_noise`` / ``image_blur`` / ``exposure`` | ``0`` / ``0`` / ``1`` | detected mode |
    | ``control_dt`` | ``0.1`` | control period, seconds |
    | ``success_position_m`` / ``success_heading_deg`` | ``0.02`` / ``2.0`` | success tolerances |
    | ``success_hold_steps`` | ``None`` | steps held within them (``None``: 1 s; 1: a pass) |
    | ``min_visible`` | ``3`` | fewer visible landmarks terminate the episode |
    | ``terminate_on_collision`` | ``True`` | |
    | ``max_landmarks`` | ``None`` | landmark slots: pad to this many, add ``landmark_mask`` |
    | ``slot_order`` | ``"fixed"`` | ``"random"``: the landmarks' slots drawn per episode |
    | ``missed_detections`` | ``None`` | ``{"rate": p, "steps": [lo, hi]}``: missed landmarks |
    | ``start_reach`` | ``1.0`` | in (0, 1]: starts near the goal, for a curriculum (below) |
    | ``goal_image_frames`` | ``1`` | noisy frames the goal image averages (parked at the goal) |
    | ``**scenario_overrides`` | | scenario keys, e.g. ``depth_scale=1.3`` |

    ```python
    import gymnasium as gym
    import radial_ibvs_gym  # registers the environments

    env = gym.make("RadialIBVS/Parking-v0", scenario="paper-sim", task=1)
    obs, info = env.reset(seed=0)
    ```

    The arguments are validated once, into a frozen
    :class:`~radial_ibvs_gym.envs.config.ParkingConfig` (``env.config``) that the native vector
    env shares; an unknown argument is an error that lists the valid ones.

    ## Version History
    - v0: initial version.
    """

    metadata: dict[str, Any] = {"render_modes": ["human", "rgb_array"], "render_fps": 10}  # noqa: RUF012
    #: the reward terms (``info["reward_<term>"]``), in the order they are summed
    reward_term_names: tuple[str, ...] = rules.REWARD_TERMS

    #: the arguments a subclass takes itself (named in the unknown-argument message)
    _own_arguments: tuple[str, ...] = ()

    def __init__(
        self, scenario: str | Path = "paper-sim", *, render_mode: str | None = None, **kwargs: Any
    ) -> None:
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(
                f"render_mode {render_mode!r} is not supported; valid: "
                f"{self.metadata['render_modes']}"
            )
        #: the validated arguments (shared with the native vector env)
        self.config = config = ParkingConfig.from_kwargs(
            scenario,
            extra=type(self)._own_arguments,
            owner=f"{type(self).__name__}.__init__",
            **kwargs,
        )
        self.render_mode = render_mode
        self._detector: DetectedPoints | None = None
        if config.measurement == "detected":
            self._detector = make_detector(config)
        self.episodes = EpisodeSource(config, self._detector)
        self.action_space = gym.spaces.Box(-1.0, 1.0, (2,), np.float32)
        self.observation_space = seen.observation_space(config)  # type: ignore[assignment]
        self._renderer: Any = None
        self.world: World | None = None
        self.episode: Episode | None = None
        self._setup: EpisodeSetup | None = None
        self._prev_errors: tuple[Any, Any] = (0.0, 0.0)
        self._held = 0  # steps in a row within the tolerances (success_hold_steps)
        self._features: FeatureErrors | None = None  # obs_mode="features": set at reset

    # --- the config's values that users and wrappers read ---------------------------------------
    @property
    def scenario(self) -> Scenario:
        """The loaded scenario (with the overrides applied)."""
        return self.config.scenario

    @property
    def robot(self) -> RobotConfig:
        """The scenario's robot."""
        return self.config.robot

    @property
    def slots(self) -> Slots | None:
        """The landmark slots (``max_landmarks``), or ``None``."""
        return self.config.slots

    @property
    def task(self) -> int | None:
        """The task index, or ``None`` (drawn per episode)."""
        return self.config.task

    @property
    def physics(self) -> str:
        """The physics backend, ``"pymunk"`` or ``"kinematic"``."""
        return self.config.physics

    @property
    def control_dt(self) -> float:
        """The control period, seconds."""
        return self.config.control_dt

    @property
    def episode_setup(self) -> EpisodeSetup | None:
        """The current episode (room, landmarks, start, goal, cameras); ``None`` before a reset.

        Read-only by convention: what a recorder or a viewer reads, not a knob.
        """
        return self._setup

    @property
    def image_points(self) -> tuple[np.ndarray, np.ndarray]:
        """The current image: normalised points ``(N, 2)`` and visibility ``(N,)``.

        Copies; the points are zeros where a landmark is not seen (the observation's ``points``
        before any slot order).
        """
        return self._points.copy(), self._visible.copy()

    @property
    def detected_frames(self) -> dict[str, np.ndarray]:
        """The last images the detector read (``measurement="detected"``).

        By ``"goal"`` and ``"current"``: ``(H, W)`` uint8 grey levels; empty for the other
        measurements.
        """
        if self._detector is None:
            return {}
        return {k: frame.image for k, frame in self._detector.last.items()}

    @property
    def start_reach(self) -> float:
        """The fraction of the start distribution drawn from (:attr:`EpisodeSource.start_reach`).

        Setting it takes effect at the next reset (a reverse curriculum raises it to 1).
        """
        return self.episodes.start_reach

    @start_reach.setter
    def start_reach(self, value: float) -> None:
        self.episodes.start_reach = value

    # --- step ----------------------------------------------------------------------------------
    def step(
        self, action: np.ndarray
    ) -> tuple[dict[str, np.ndarray], float, bool, bool, dict[str, Any]]:
        """Apply one action for ``control_dt`` seconds (see the class docstring)."""
        if self.world is None or self._setup is None:
            raise RuntimeError("call reset() before step()")
        config = self.config
        if type(action) is np.ndarray and action.shape == (2,) and action.dtype.char in "fd":
            a0, a1 = action.tolist()  # the action space's own float32 (or float64): exact
        else:
            a = rules.real_actions(action).reshape(-1)
            if a.shape != (2,):
                raise ValueError(f"action must be {rules.ACTION_RULE}, got {action!r}")
            a0, a1 = a.tolist()
        if not (math.isfinite(a0) and math.isfinite(a1)):
            raise ValueError(f"action must be {rules.ACTION_RULE}, got {action!r}")
        # rules.twist_commands on Python floats (the hot path of one robot; tested equal)
        s0, s1 = config.scale
        command = (min(max(a0, -1.0), 1.0) * s0, min(max(a1, -1.0), 1.0) * s1)
        if config.action_type == "wheels":
            command = tuple(wheels_to_twist(command, config.robot).tolist())
        result = self.world.step(command, config.control_dt)
        self._observe(result.pose)
        now = rules.pose_errors(result.pose.tolist(), self._goal)
        success, lost, terminated, self._held = rules.episode_end(
            *now,
            self._n_visible,
            result.collision,
            success_position_m=config.success_position_m,
            success_heading_rad=config.success_heading_rad,
            min_visible=config.min_visible,
            terminate_on_collision=config.terminate_on_collision,
            held=self._held,
            hold_steps=config.hold_steps,
        )
        terms = self._reward_terms(self._prev_errors, now, result.collision, lost, success)
        self._prev_errors = now
        reached = self._held == 1
        info = self._info(
            result.pose, now, bool(success), result.collision, bool(lost), reached=reached
        )
        info.update(rules.reward_info(terms, np.float64))
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
        config = self.config
        options = dict(options or {})
        unknown = sorted(set(options) - {"start", "goal", "task"})
        if unknown:
            raise ValueError(f"unknown reset option(s) {unknown}; valid: ['goal', 'start', 'task']")
        task = options.get("task", config.task)
        setup = self.episodes.setup_episode(self.np_random, task, options)
        episode = setup.episode
        self._setup, self.episode = setup, episode
        self._goal = tuple(episode.goal.tolist())
        room = (float(episode.room[0]), float(episode.room[1]))
        extra = {"physics_dt": config.physics_dt} if config.physics == "pymunk" else {}
        obstacles = tuple(tuple(o) for o in episode.obstacles.tolist())
        self.world = make_world(config.physics, config.robot, room, obstacles=obstacles, **extra)
        self.world.reset(episode.start)
        self._features = None
        if config.obs_mode == "features":
            assert setup.c_goal is not None
            self._features = FeatureErrors(1, len(setup.goal_points), config.pairs)
            self._features.start(0, setup.c_goal, setup.goal_points)
        if self._detector is not None:
            self._points, self._visible = self._detector.initial()
            self._n_visible = int(np.count_nonzero(self._visible))
            self._update_features()
        else:
            self._observe(episode.start)
        self._prev_errors = rules.pose_errors(episode.start.tolist(), self._goal)
        self._held = 0  # steps in a row within the tolerances
        self._renderer = None
        self._trail: list[np.ndarray] = [episode.start[:2].copy()]
        if self.render_mode == "human":
            self.render()
        info = self._info(episode.start, self._prev_errors, False, False)
        info |= rules.reward_info(dict.fromkeys(self.reward_term_names, np.float64(0.0)))
        return self._obs(), info

    # --- rendering -----------------------------------------------------------------------------
    def _status(self) -> str:
        """Return the rendered frame's caption: time, errors, whether the robot is parked."""
        position, heading = self._prev_errors
        config = self.config
        parked = position <= config.success_position_m and heading <= config.success_heading_rad
        return (
            f"t = {(len(self._trail) - 1) * config.control_dt:.1f} s, error "
            f"{100 * position:.1f} cm, {math.degrees(heading):.1f} deg"
            + (": parked" if parked else "")
        )

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
        frame: np.ndarray = self._renderer.frame(self.world.pose, self._trail, self._status())
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
    def image(
        self, setup: EpisodeSetup, pose: np.ndarray, which: str, rng: np.random.Generator
    ) -> tuple[np.ndarray, np.ndarray]:
        """Normalised image points ``(N, 2)`` and visibility ``(N,)`` at a pose.

        :meth:`EpisodeSource.image`: ``which`` is ``"current"`` (the scenario's camera) or
        ``"goal"`` (its goal camera); ``pose`` ``(3,)`` metres and radians.
        """
        return self.episodes.image(setup, pose, which, rng)

    def _observe(self, pose: np.ndarray) -> None:
        assert self._setup is not None
        if self._detector is not None:
            self._points, self._visible = self._detector.observe(pose, self.np_random)
        else:
            self._points, self._visible = self.episodes.image(
                self._setup, pose, "current", self.np_random
            )
            if self._setup.missed is not None:
                self._points, self._visible = self._setup.missed.apply(self._points, self._visible)
        self._n_visible = int(np.count_nonzero(self._visible))
        self._update_features()

    def _update_features(self) -> None:
        """Take the landmarks visible now and in the goal image (``obs_mode="features"``)."""
        if self._features is not None:
            assert self._setup is not None
            both = self._visible & self._setup.goal_visible
            self._features.update(_ROW, both[None])

    def _reward_terms(
        self,
        previous: tuple[Any, Any],
        now: tuple[Any, Any],
        collision: Any,
        lost: Any,
        success: Any,
    ) -> dict[str, Any]:
        """Return the step's named reward terms (the reward hook, the vector env's too).

        ``previous`` and ``now`` are the pose errors (metres, radians) before and after the
        step. ``Parking-v0``'s terms (:func:`~radial_ibvs_gym.envs.rules.reward_terms`);
        ``ParkingGoal-v1`` overrides it with its goal reward.
        """
        return rules.reward_terms(previous, now, collision, lost, success, self.config.weights)

    def _images(self) -> tuple[np.ndarray, np.ndarray]:
        """Return the current and the goal image points, ``(N, 2)`` each (zeros where hidden)."""
        assert self._setup is not None
        return self._points, self._setup.goal_points

    def _obs(self) -> dict[str, np.ndarray]:
        assert self._setup is not None
        obs = self._image_obs()
        if self._setup.map is not None:
            obs.update({key: value.copy() for key, value in self._setup.map.items()})
        return obs

    def _image_obs(self) -> dict[str, np.ndarray]:
        assert self._setup is not None
        config = self.config
        features = None
        if self._features is not None:
            c_err, a_err = self._features.errors(self._points[None])
            features = {"c_error": c_err[0], "alpha_m_error": a_err[0]}
        pose = self.world.pose if config.privileged and self.world is not None else None
        return seen.observation(
            self._points.reshape(-1),
            self._setup.goal_points.reshape(-1),
            self._visible,
            features=features,
            goal_depths=self._setup.goal_depths if config.goal_depths else None,
            robot_pose=pose,
            goal_pose=self._setup.privileged_goal if config.privileged else None,
            landmarks=self._setup.landmarks_c if config.privileged else None,
            slots=config.slots,
            slot_order=self._setup.slot_order,
            present=self._setup.present,
        )

    def _info(
        self,
        pose: np.ndarray,
        errors: tuple[Any, Any],
        success: bool,
        collision: bool,
        lost: bool = False,
        *,
        reached: bool = False,
    ) -> dict[str, Any]:
        setup = self._setup
        assert setup is not None
        drawn = setup.imperfections
        info = rules.info_values(
            pose,
            setup.episode.goal,
            errors,
            success,
            collision,
            lost,
            self._n_visible,
            setup.episode.task,
            setup.goal_depths,
            None if drawn is None else rules.imperfections_info(drawn),
            reached=reached,
        )
        if self._detector is not None:
            info["detection"] = self._detector.info()
        return info
