"""Native vector envs: ``N`` robots stepped in one batched call (``gym.make_vec``).

``gym.make_vec("RadialIBVS/Parking-v0", num_envs=N, vectorization_mode="vector_entry_point")``
(and the same for ``ParkingGoal-v1``) builds a :class:`ParkingVectorEnv`: one
``gymnasium.vector.VectorEnv`` that steps all ``N`` robots with batched numpy (the
:mod:`~radial_ibvs_gym.physics.fleet` physics, the observation, visibility, reward terms,
termination and truncation of :mod:`~radial_ibvs_gym.envs.observation` and
:mod:`~radial_ibvs_gym.envs.rules`, the code the scalar envs run). It takes the scalar env's
keyword arguments, validated into the same :class:`~radial_ibvs_gym.envs.config.ParkingConfig`,
and gives the same numbers as ``gym.make_vec(..., vectorization_mode="sync")`` on the same
seeds and actions.

One class of about 545 lines: its reset, its step with its three autoreset modes, its observation
and its info share the ``(N, ...)`` arrays it holds, so they stay together; the info helpers are
in :mod:`~radial_ibvs_gym.envs.vector_info`, the goal-conditioned variant in
:mod:`~radial_ibvs_gym.envs.parking_goal`.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from gymnasium import spaces
from gymnasium.utils import seeding
from gymnasium.vector import VectorEnv
from gymnasium.vector.utils import batch_space
from numpy.typing import NDArray

from radial_ibvs_gym.envs import observation as seen
from radial_ibvs_gym.envs import rules
from radial_ibvs_gym.envs.autoreset import AutoresetMode
from radial_ibvs_gym.envs.config import ParkingConfig
from radial_ibvs_gym.envs.episodes import EpisodeSetup, EpisodeSource
from radial_ibvs_gym.envs.rules import IMPERFECTION_KEYS
from radial_ibvs_gym.envs.vector_info import masked, put, select, spread
from radial_ibvs_gym.limits import MAX_NUM_ENVS
from radial_ibvs_gym.physics.fleet import make_fleet
from radial_ibvs_gym.registration import MAX_EPISODE_STEPS

__all__ = ["ParkingVectorEnv"]

#: accepted spellings: Gymnasium's values (``"NextStep"``) and snake case (``"next_step"``)
_MODES = {k: m for m in AutoresetMode for k in (m.value, m.name.lower())}


class ParkingVectorEnv(VectorEnv):
    """``RadialIBVS/Parking-v0`` for ``num_envs`` robots at once, batched in numpy.

    ## Description
    The task, spaces, rewards and episode end of
    :class:`~radial_ibvs_gym.envs.parking.ParkingEnv`, for ``N`` robots. Each env has its own
    generator (``reset(seed=s)`` seeds env ``i`` with ``s + i``, as ``SyncVectorEnv``
    does), its own episode and, in ``random`` rooms, its own room and landmarks. The physics
    is batched: the ``kinematic`` unicycle in numpy, or all ``N`` pymunk robots in one
    ``pymunk.Space`` with their rooms placed apart (:mod:`radial_ibvs_gym.physics.fleet`).

    ## Spaces
    ``single_observation_space`` and ``single_action_space`` are the scalar env's;
    ``observation_space`` and ``action_space`` batch them (leading ``N``).

    ## Autoreset
    ``metadata["autoreset_mode"]`` is the ``autoreset_mode`` argument (Gymnasium's
    ``AutoresetMode``): ``"next_step"`` (default, as ``SyncVectorEnv``: the step after an
    episode ends resets that env, ignoring its action, with reward 0) or ``"same_step"`` (the
    env is reset in the step that ends it; ``info["final_obs"]`` and ``info["final_info"]``
    hold the last observation and info) or ``"disabled"`` (no env is reset by ``step``: an
    env that ended steps on if asked, its camera off: its observation stays that of the step
    that ended it, and an imperfect camera draws no more noise, until the caller resets it).
    ``reset(options={"reset_mask": mask})`` resets only the masked envs.

    ## Info
    A dict of arrays (Gymnasium's vector convention): every key of the scalar env's ``info``
    with a leading ``N``, and its ``_key`` mask of the envs that reported it.

    ## Arguments
    ``num_envs`` (>= 1), ``autoreset_mode``, ``max_episode_steps`` (the time limit; the
    registration's 600 by default), and every keyword argument of ``ParkingEnv``.
    ``measurement="detected"`` and ``render_mode`` are not batched: use
    ``vectorization_mode="sync"`` for them.

    ## Errors
    A NaN or infinite action raises ``ValueError`` naming the env; so does an action of the
    wrong shape, and ``num_envs < 1``.

    ```python
    import gymnasium as gym
    import radial_ibvs_gym  # registers the environments

    envs = gym.make_vec("RadialIBVS/Parking-v0", num_envs=256, physics="kinematic")
    obs, info = envs.reset(seed=0)
    obs, reward, terminated, truncated, info = envs.step(envs.action_space.sample())
    ```
    """

    metadata: dict[str, Any] = {"autoreset_mode": AutoresetMode.NEXT_STEP}  # noqa: RUF012
    #: the reward terms (``info["reward_<term>"]``), in the order they are summed
    reward_term_names: tuple[str, ...] = rules.REWARD_TERMS
    #: the arguments a subclass takes itself (named in the unknown-argument message)
    _own_arguments: tuple[str, ...] = ()

    def __init__(
        self,
        num_envs: int = 1,
        *,
        autoreset_mode: AutoresetMode | str = AutoresetMode.NEXT_STEP,
        max_episode_steps: int | None = MAX_EPISODE_STEPS,
        render_mode: str | None = None,
        **kwargs: Any,
    ) -> None:
        if isinstance(num_envs, bool) or not isinstance(num_envs, int | np.integer) or num_envs < 1:
            raise ValueError(f"num_envs must be an integer >= 1, got {num_envs!r}")
        if num_envs > MAX_NUM_ENVS:
            raise ValueError(
                f"num_envs must be at most MAX_NUM_ENVS = {MAX_NUM_ENVS}, got {num_envs}"
            )
        if render_mode is not None:
            raise ValueError(
                "the native vector env does not render; use gym.make_vec(..., "
                "vectorization_mode='sync', render_mode=...) or a scalar env"
            )
        if kwargs.get("measurement", "ideal") == "detected":
            raise ValueError(
                "measurement='detected' renders and detects images per env and is not batched; "
                "use gym.make_vec(..., vectorization_mode='sync')"
            )
        if isinstance(autoreset_mode, str):
            if autoreset_mode not in _MODES:
                raise ValueError(
                    f"unknown autoreset_mode {autoreset_mode!r}; valid: {sorted(_MODES)}"
                )
            autoreset_mode = _MODES[autoreset_mode]
        if max_episode_steps is not None and max_episode_steps < 1:
            raise ValueError(f"max_episode_steps must be >= 1, got {max_episode_steps!r}")
        #: the validated arguments, as the scalar env holds them
        self.config = config = ParkingConfig.from_kwargs(
            extra=self._own_arguments, owner=f"{type(self).__name__}.__init__", **kwargs
        )
        self.episodes = EpisodeSource(config)
        self.num_envs = n = int(num_envs)
        self.autoreset_mode = autoreset_mode
        self.metadata = {**type(self).metadata, "autoreset_mode": autoreset_mode}
        self.render_mode = None
        self.max_episode_steps = max_episode_steps
        self.scenario = config.scenario
        self.single_observation_space = self._single_observation_space()
        self.single_action_space = spaces.Box(-1.0, 1.0, (2,), np.float32)
        self.observation_space = batch_space(self.single_observation_space, n)
        self.action_space = batch_space(self.single_action_space, n)
        scene = config.scenario.config
        room = scene.random_room
        max_room = (room.width[1], room.depth[1]) if room is not None else tuple(scene.room)
        extra = {"physics_dt": config.physics_dt, "max_room": max_room}
        self.fleet = make_fleet(config.physics, config.robot, n, obstacles=scene.obstacles, **extra)
        nl = self.scenario.n_landmarks
        self._rngs: list[np.random.Generator | None] = [None] * n
        self._setups: list[EpisodeSetup | None] = [None] * n
        self._landmarks_c = np.zeros((n, nl), dtype=np.complex128)
        self._landmarks_w = np.zeros((n, nl, 3))  # world frame (the imperfect camera's input)
        self._bounds = np.zeros((2, n, nl))  # current camera: visible distance interval
        self._goals = np.zeros((n, 3))
        self._privileged_goals = np.zeros((n, 3))  # the image goal with privileged_goal="image"
        self._held = np.zeros(n, dtype=np.int64)  # steps in a row within the tolerances
        self._tasks = np.zeros(n, dtype=np.int64)
        self._goal_points = np.zeros((n, nl, 2))
        self._goal_visible = np.zeros((n, nl), dtype=bool)
        self._goal_depths = np.zeros((n, nl))
        self._points = np.zeros((n, nl, 2))
        self._visible = np.zeros((n, nl), dtype=bool)
        self._prev = (np.zeros(n), np.zeros(n))
        self._elapsed = np.zeros(n, dtype=np.int64)
        self._autoreset = np.zeros(n, dtype=bool)
        self._ended = np.zeros(n, dtype=bool)  # autoreset "disabled": ended, not reset since
        self._slot_orders = np.zeros((n, nl), dtype=np.intp)  # slot_order="random": per env
        camera = self.scenario.config.camera
        self._drawn = camera.imperfection_ranges is not None  # imperfections drawn per episode
        self._fast = not (camera.imperfections.any or self._drawn)
        #: the drawn imperfections per env, columns as in logic.imperfections_info
        self._imperfections = np.zeros((n, len(IMPERFECTION_KEYS)))
        if config.obs_mode == "features":
            m = len(config.pairs[0])
            self._c_goal = np.zeros((n, m))
            self._weights = np.zeros((n, nl))
            self._has_weights = np.zeros(n, dtype=bool)
            self._both = np.zeros((n, nl), dtype=bool)
            self._weight_caches: list[dict[bytes, NDArray[np.float64] | None]] = [
                {} for _ in range(n)
            ]

    def _single_observation_space(self) -> spaces.Space[Any]:
        """One robot's observation space (the scalar env's)."""
        return seen.observation_space(self.config)

    @property
    def start_reach(self) -> float:
        """``start_reach`` (a curriculum knob, as the scalar env's), shared by every env.

        Setting it takes effect at each env's next reset (autoresets included).
        """
        return self.episodes.start_reach

    @start_reach.setter
    def start_reach(self, value: float) -> None:
        self.episodes.start_reach = value

    # --- reset ---------------------------------------------------------------------------------
    def reset(
        self,
        *,
        seed: int | list[int | None] | None = None,
        options: dict[str, Any] | None = None,
    ) -> tuple[Any, dict[str, Any]]:
        """Reset every env (or those of ``options["reset_mask"]``); env ``i`` gets ``seed + i``."""
        n = self.num_envs
        if seed is None:
            seeds: list[int | None] = [None] * n
        elif isinstance(seed, int | np.integer):
            seeds = [int(seed) + i for i in range(n)]
        else:
            seeds = list(seed)
            if len(seeds) != n:
                raise ValueError(f"seed must be an int or {n} seeds, got {len(seeds)}")
        options = dict(options or {})
        mask = options.pop("reset_mask", None)
        if mask is None:
            mask = np.ones(n, dtype=bool)
        else:
            mask = np.asarray(mask)
            if mask.shape != (n,) or mask.dtype != np.bool_ or not mask.any():
                raise ValueError(
                    f"options['reset_mask'] must be a bool array of shape ({n},) with a True"
                )
        for i in np.flatnonzero(mask).tolist():
            if seeds[i] is not None or self._rngs[i] is None:
                self._rngs[i] = seeding.np_random(seeds[i])[0]
        indices = np.flatnonzero(mask)
        self._reset_envs(indices, options)
        self._autoreset[indices] = False
        self._ended[indices] = False
        info = self._reset_info(indices)
        return self._observation(), info

    def _reset_envs(self, indices: NDArray[np.intp], options: dict[str, Any]) -> None:
        """Draw new episodes for the envs ``indices`` (each with its own generator)."""
        t = self.config
        unknown = sorted(set(options) - {"start", "goal", "task"})
        if unknown:
            raise ValueError(f"unknown reset option(s) {unknown}; valid: ['goal', 'start', 'task']")
        task = options.get("task", t.task)
        rooms, starts, obstacles = [], [], []
        for i in indices.tolist():
            rng = self._rngs[i]
            assert rng is not None
            setup = self.episodes.setup_episode(rng, task, options)
            episode = setup.episode
            self._landmarks_c[i] = setup.landmarks_c
            self._landmarks_w[i] = episode.landmarks
            if self._fast:
                bounds = setup.radius_bounds["current"]
                assert bounds is not None
                self._bounds[0, i], self._bounds[1, i] = bounds
            self._goals[i] = episode.goal
            self._privileged_goals[i] = setup.privileged_goal
            self._tasks[i] = episode.task
            self._goal_points[i] = setup.goal_points
            self._goal_visible[i] = setup.goal_visible
            self._goal_depths[i] = setup.goal_depths
            self._setups[i] = setup
            if setup.slot_order is not None:
                self._slot_orders[i] = setup.slot_order
            if setup.imperfections is not None:
                drawn = rules.imperfections_info(setup.imperfections)
                self._imperfections[i] = [drawn[k] for k in IMPERFECTION_KEYS]
            rooms.append(episode.room)
            starts.append(episode.start)
            obstacles.append(episode.obstacles)
            if t.obs_mode == "features":
                self._c_goal[i] = setup.c_goal
                self._weight_caches[i] = {}
                self._both[i] = False
                self._weights[i] = 0.0
                self._has_weights[i] = False
        self.fleet.reset(indices, np.array(rooms), np.array(starts), obstacles)
        poses = self.fleet.poses
        self._observe(poses, indices)
        goals = self._goals[indices].T
        errors = rules.pose_errors(poses[indices].T, goals)
        self._prev[0][indices], self._prev[1][indices] = errors
        self._elapsed[indices] = 0
        self._held[indices] = 0

    # --- step ----------------------------------------------------------------------------------
    def step(
        self, actions: Any
    ) -> tuple[Any, NDArray[np.float64], NDArray[np.bool_], NDArray[np.bool_], dict[str, Any]]:
        """Step every env; see the class docstring for autoreset and the info arrays."""
        n, t = self.num_envs, self.config
        a = rules.real_actions(actions)
        if a.shape != (n, 2):
            raise ValueError(
                f"actions must have shape ({n}, 2) (one (v, omega) row per env), got {a.shape}"
            )
        finite = np.isfinite(a).all(axis=1)
        if not finite.all():
            i = int(np.argmin(finite))
            raise ValueError(f"env {i}: action must be {rules.ACTION_RULE}, got {a[i].tolist()}")
        if not any(self._rngs):
            raise RuntimeError("call reset() before step()")
        resetting = (
            self._autoreset.copy() if self.autoreset_mode == AutoresetMode.NEXT_STEP else None
        )
        command = np.clip(a, -1.0, 1.0) * np.array(t.scale)
        if t.action_type == "wheels":
            from radial_ibvs_gym.physics import wheels_to_twist

            command = wheels_to_twist(command, t.robot)
        if resetting is not None and resetting.any():
            command[resetting] = 0.0  # ignored: these envs are reset below
        poses, collision = self.fleet.step(command, t.control_dt)
        if resetting is not None and resetting.any():
            # the envs being reset do not observe: an imperfect camera's noise would use up
            # their generators, which their reset must find as SyncVectorEnv leaves them
            self._observe(poses, np.flatnonzero(~resetting))
        elif self.autoreset_mode == AutoresetMode.DISABLED and self._ended.any():
            self._observe(poses, np.flatnonzero(~self._ended))  # the ended ones: camera off
        else:
            self._observe(poses, np.arange(n))
        now = rules.pose_errors(poses.T, self._goals.T)
        n_visible = self._visible.sum(axis=1)
        success, lost, terminated, self._held = rules.episode_end(
            *now,
            n_visible,
            collision,
            success_position_m=t.success_position_m,
            success_heading_rad=t.success_heading_rad,
            min_visible=t.min_visible,
            terminate_on_collision=t.terminate_on_collision,
            held=self._held,
            hold_steps=t.success_hold_steps,
        )
        terms = self._reward_terms(self._prev, now, collision, lost, success)
        reward = sum(terms.values(), np.zeros(n))
        self._prev = now
        self._elapsed += 1
        truncated = (
            self._elapsed >= self.max_episode_steps
            if self.max_episode_steps is not None
            else np.zeros(n, dtype=bool)
        )
        info = self._info(poses, now, success, collision, n_visible, lost)
        info |= masked(rules.reward_info(terms), np.ones(n, dtype=bool))
        obs = self._observation()
        if resetting is not None:
            if resetting.any():
                idx = np.flatnonzero(resetting)
                self._reset_envs(idx, {})
                reward[idx] = 0.0
                terminated[idx] = False
                truncated[idx] = False
                self._refresh(obs, idx)
                self._merge_reset_info(info, idx)
            self._autoreset = terminated | truncated
        elif self.autoreset_mode == AutoresetMode.DISABLED:
            self._ended |= terminated | truncated
        elif self.autoreset_mode == AutoresetMode.SAME_STEP:  # the envs that ended reset now
            ended = terminated | truncated
            if ended.any():
                idx = np.flatnonzero(ended)
                final_obs = np.full(n, None, dtype=object)
                for i in idx.tolist():
                    final_obs[i] = {k: v[i].copy() for k, v in obs.items()}
                final_info = select(info, ended)
                self._reset_envs(idx, {})
                self._refresh(obs, idx)
                self._merge_reset_info(info, idx)
                info["final_obs"], info["_final_obs"] = final_obs, ended.copy()
                info["final_info"], info["_final_info"] = final_info, ended.copy()
        return obs, reward, terminated, truncated, info

    def _reward_terms(
        self,
        previous: tuple[NDArray[np.float64], NDArray[np.float64]],
        now: tuple[NDArray[np.float64], NDArray[np.float64]],
        collision: NDArray[np.bool_],
        lost: NDArray[np.bool_],
        success: NDArray[np.bool_],
    ) -> dict[str, NDArray[np.float64]]:
        return rules.reward_terms(previous, now, collision, lost, success, self.config.weights)

    # --- observation and info ------------------------------------------------------------------
    def _observe(self, poses: NDArray[np.float64], indices: NDArray[np.intp]) -> None:
        """Image points and visibility of the envs ``indices`` at their ``poses`` ``(N, 3)``."""
        if self._fast:
            if len(indices) == self.num_envs:
                pts, vis = seen.radial_image(
                    self._landmarks_c, self._bounds[0], self._bounds[1], poses
                )
            else:
                pts, vis = seen.radial_image(
                    self._landmarks_c[indices],
                    self._bounds[0, indices],
                    self._bounds[1, indices],
                    poses[indices],
                )
            self._points[indices], self._visible[indices] = pts, vis
            if self.config.missed_detections is not None:
                for i in indices.tolist():
                    missed = self._setups[i].missed
                    self._points[i], self._visible[i] = missed.apply(
                        self._points[i], self._visible[i]
                    )
        elif len(indices):  # a camera with imperfections: exact projection and noise, batched
            rows = indices.tolist()
            setups = [self._setups[i] for i in rows]
            rngs = [self._rngs[i] for i in rows]
            assert all(s is not None for s in setups) and all(r is not None for r in rngs)
            cameras = [s.cameras["current"] for s in setups]
            p_cam = self._camera_frame(poses[indices], indices)
            points, visible = seen.camera_images(cameras, p_cam, rngs)
            self._points[indices], self._visible[indices] = points, visible
            for i, setup in zip(rows, setups, strict=True):
                if setup is not None and setup.missed is not None:
                    self._points[i], self._visible[i] = setup.missed.apply(
                        self._points[i], self._visible[i]
                    )
        if self.config.obs_mode == "features":
            both = self._visible[indices] & self._goal_visible[indices]
            changed = (both != self._both[indices]).any(axis=1)
            for k in np.flatnonzero(changed).tolist():
                i = int(indices[k])
                key = both[k].tobytes()
                cache = self._weight_caches[i]
                if key not in cache:
                    cache[key] = seen.goal_weights(self._goal_points[i], both[k])
                a = cache[key]
                self._has_weights[i] = a is not None
                self._weights[i] = 0.0 if a is None else a
            self._both[indices] = both

    def _camera_frame(self, poses: NDArray[np.float64], indices: NDArray[np.intp]) -> Any:
        """Landmarks ``(k, N, 3)`` of the envs ``indices`` in their cameras' frames, metres.

        :func:`~radial_ibvs_gym.geometry.world_to_camera` batched, with each yaw's cosine and
        sine taken as the scalar env takes them (``math``), so the numbers are its own.
        """
        landmarks = self._landmarks_w[indices]
        yaw = poses[:, 2].tolist()
        c = np.array([math.cos(a) for a in yaw])[:, None]
        s = np.array([math.sin(a) for a in yaw])[:, None]
        dx = landmarks[..., 0] - poses[:, 0, None]
        dy = landmarks[..., 1] - poses[:, 1, None]
        z = landmarks[..., 2] - self.config.scenario.config.camera_height
        return np.stack([c * dx + s * dy, -s * dx + c * dy, z], axis=-1)

    def _observation(self, idx: Any = slice(None)) -> dict[str, NDArray[Any]]:
        """Return the observations of the envs ``idx`` (default: all)."""
        t = self.config
        points = self._points[idx]
        extra: dict[str, NDArray[Any]] = {}
        if t.obs_mode == "features":
            c_err, a_err = seen.feature_errors(
                points,
                self._both[idx],
                self._c_goal[idx],
                t.pairs,
                self._weights[idx],
                self._has_weights[idx],
            )
            extra = {"c_error": c_err, "alpha_m_error": a_err}
        obs = seen.observation(
            points.reshape(len(points), -1),
            self._goal_points[idx].reshape(len(points), -1),
            self._visible[idx],
            features=extra,
            goal_depths=self._goal_depths[idx] if t.goal_depths else None,
            robot_pose=self.fleet.poses[idx] if t.privileged else None,
            goal_pose=self._privileged_goals[idx] if t.privileged else None,
            landmarks=self._landmarks_c[idx] if t.privileged else None,
            slots=t.slots,
            slot_order=self._slot_orders[idx] if t.slot_order == "random" else None,
        )
        if t.privileged_map:
            setups = [self._setups[i] for i in np.arange(self.num_envs)[idx].tolist()]
            maps = [s.map for s in setups if s is not None and s.map is not None]
            for key in ("room", "obstacles", "landmarks", "landmark_range"):
                obs[key] = np.stack([m[key] for m in maps])
        return obs

    def _refresh(self, obs: dict[str, NDArray[Any]], idx: NDArray[np.intp]) -> None:
        """Overwrite the rows ``idx`` of ``obs`` with those envs' current observations."""
        fresh = self._observation(idx)
        for key, value in obs.items():
            value[idx] = fresh[key]

    def _info(
        self,
        poses: NDArray[np.float64],
        errors: tuple[NDArray[np.float64], NDArray[np.float64]],
        success: NDArray[np.bool_],
        collision: NDArray[np.bool_],
        n_visible: NDArray[np.integer[Any]],
        lost: NDArray[np.bool_] | None = None,
    ) -> dict[str, Any]:
        values = rules.info_values(
            poses,
            self._goals,
            errors,
            success,
            collision,
            np.zeros(self.num_envs, bool) if lost is None else lost,
            n_visible,
            self._tasks,
            self._goal_depths,
            self._imperfections_info(slice(None)),
        )
        return masked(values, np.ones(self.num_envs, dtype=bool))

    def _imperfections_info(self, rows: Any) -> dict[str, Any] | None:
        """Return the drawn imperfections of the envs ``rows`` (``{key: (k,) array}``) or None."""
        if not self._drawn:
            return None
        table = self._imperfections[rows]
        return {k: table[:, j] for j, k in enumerate(IMPERFECTION_KEYS)}

    def _reset_values(self, indices: NDArray[np.intp]) -> dict[str, Any]:
        """Return the reset ``info`` values of the envs ``indices`` (rows of each key)."""
        no = np.zeros(len(indices), dtype=bool)
        values = rules.info_values(
            self.fleet.poses[indices],
            self._goals[indices],
            (self._prev[0][indices], self._prev[1][indices]),
            no,
            no,
            no,
            self._visible[indices].sum(axis=1),
            self._tasks[indices],
            self._goal_depths[indices],
            self._imperfections_info(indices),
        )
        zero = np.zeros(len(indices))
        return values | rules.reward_info({k: zero for k in self.reward_term_names})

    def _reset_info(self, indices: NDArray[np.intp]) -> dict[str, Any]:
        """Return the ``info`` of :meth:`reset`: the reset envs' rows, the others masked."""
        mask = np.zeros(self.num_envs, dtype=bool)
        mask[indices] = True
        return spread(self._reset_values(indices), indices, mask)

    def _merge_reset_info(self, info: dict[str, Any], indices: NDArray[np.intp]) -> None:
        """Replace the entries of the envs just reset by their reset info (as SyncVectorEnv)."""
        put(info, self._reset_values(indices), indices)

    def close_extras(self, **kwargs: Any) -> None:
        """Release the physics."""
        self.fleet = None  # type: ignore[assignment]
